#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include "math/ray_spawn.h"
#include "math/rng.h"
#include "render/denoise.h"
#include "render/denoising_features.h"
#include "render/film.h"
#include "render/path_regularization.h"
#include "render/ray_cone.h"
#include "render/render_origin.h"
#include "render/shading.h"
#include "base/input_error.h"

namespace purl {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kTileSize = 16;
constexpr int kRouletteDepth = 3;
constexpr int kMaxPassThroughs = 64;  // yarns a ray may cross between plies before it gives up

size_t peak_resident_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<size_t>(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The film and its passes take about 76 bytes a pixel; the JSON reader allows 32768 pixels
// a side, whose film alone would be 76 GiB. Refused before anything is allocated.
void check_film_size(const FilmDesc& film, const std::string& source) {
    constexpr uint64_t kMaxFilmPixels = uint64_t(1) << 26;  // 8192 x 8192, about 5 GiB
    const uint64_t pixels = uint64_t(std::max(film.width, 0)) * uint64_t(std::max(film.height, 0));
    if (pixels == 0 || pixels > kMaxFilmPixels) {
        const uint64_t bytes = pixels * (sizeof(PixelResult) + 9 * sizeof(float));
        throw InputError(source, "film",
                         std::to_string(film.width) + " x " + std::to_string(film.height) +
                             " pixels: a render may have 1 to " + std::to_string(kMaxFilmPixels) +
                             " pixels (8192 x 8192); this film and its passes would take " +
                             std::to_string(bytes >> 30) + " GiB");
    }
}

// The scene as rendered: centred on its cloth (render/render_origin.h), then made explicit when
// the render asks for the ply or fiber reference.
SceneDesc scene_to_render(SceneDesc scene, ExplicitSceneBuilder make_explicit) {
    move_to_render_origin(scene, render_origin(scene));
    if (scene.render.model == YarnModel::Bysdf) return scene;
    if (!make_explicit)
        throw InputError(scene.source, "render.model",
                         "the ply and fiber references need the explicit scene builder (reference/explicit_models.h)");
    return make_explicit(scene, scene.render.model);
}

}  // namespace

struct Renderer::PathTotals {
    uint64_t rays = 0, interactions = 0, invalid = 0;
    uint64_t hits_by_mode[3] = {0, 0, 0};  // near, multi, far: camera hits on BYSDF yarns
    uint64_t h_samples = 0;
};

Renderer::Renderer(SceneDesc scene, ExplicitSceneBuilder make_explicit)
    : scene_(scene_to_render(std::move(scene), make_explicit)), camera_(scene_.camera, scene_.film) {
    check_film_size(scene_.film, scene_.source);
    const auto start = Clock::now();
    geometry_ = std::make_unique<EmbreeScene>(scene_);
    lights_ = std::make_unique<Lights>(scene_);
    shader_ = std::make_unique<SurfaceShader>(scene_);
    uint32_t base = 0;
    for (const YarnSetDesc& y : scene_.yarns) {
        yarn_id_base_.push_back(base);
        base += static_cast<uint32_t>(y.curves.curve_count());
    }
    build_seconds_ = seconds_since(start);
}

Renderer::~Renderer() = default;

void Renderer::set_view(const CameraDesc& camera, const FilmDesc& film, const Point64& camera_origin) {
    check_film_size(film, scene_.source);
    CameraDesc moved = camera;  // into the frame the scene was moved to, in double
    for (int r = 0; r < 3; ++r)
        moved.to_world.m[r][3] = float((double(camera.to_world.m[r][3]) + camera_origin[r]) - scene_.origin[r]);
    camera_ = Camera(moved, film);
    scene_.camera = moved;
    scene_.film = film;
}

RenderResult Renderer::render(RenderControl& control) const { return render(scene_.render, control); }

RenderResult Renderer::render(const RenderSettings& settings, RenderControl& control) const {
    const int width = scene_.film.width, height = scene_.film.height;
    const int tiles_x = (width + kTileSize - 1) / kTileSize, tiles_y = (height + kTileSize - 1) / kTileSize;
    Film film(width, height);
    control.pixels_done = 0;
    control.pixels_total = uint64_t(width) * height;

    std::atomic<uint64_t> rays{0}, interactions{0}, invalid{0};
    std::atomic<uint64_t> hits_near{0}, hits_multi{0}, hits_far{0}, h_samples{0}, bysdf_evaluations{0};
    // The selector warns once per render (far forced on yarns wider than a pixel); the
    // warning goes into the stats, and front ends show it (CLI: stderr).
    std::mutex warnings_mutex;
    std::vector<std::string> warnings;
    const MultiscaleSelector multiscale(
        settings.multiscale,
        [&](const std::string& message) {
            const std::lock_guard<std::mutex> lock(warnings_mutex);
            warnings.push_back(message);
        },
        scene_.yarns.size());
    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    // Before any work: a missing OIDN fails here, not after the samples.
    const std::shared_ptr<const Denoiser> denoiser = settings.denoise ? Denoiser::load() : nullptr;
    tbb::task_arena arena(threads);
    const auto start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(0, tiles_x * tiles_y, 1),
            [&](const tbb::blocked_range<int>& range) {
                for (int tile = range.begin(); tile != range.end(); ++tile) {
                    PathTotals totals;
                    const uint64_t evaluations_before = bysdf_evaluations_on_this_thread();
                    const int x0 = (tile % tiles_x) * kTileSize, y0 = (tile / tiles_x) * kTileSize;
                    const int x1 = std::min(width, x0 + kTileSize), y1 = std::min(height, y0 + kTileSize);
                    for (int y = y0; y < y1; ++y)
                        for (int x = x0; x < x1; ++x) {
                            if (control.cancel.load(std::memory_order_relaxed)) return;
                            render_pixel(x, y, settings, multiscale, film.at(x, y), totals);
                            control.pixels_done.fetch_add(1, std::memory_order_relaxed);
                        }
                    rays += totals.rays;
                    interactions += totals.interactions;
                    invalid += totals.invalid;
                    hits_near += totals.hits_by_mode[0];
                    hits_multi += totals.hits_by_mode[1];
                    hits_far += totals.hits_by_mode[2];
                    h_samples += totals.h_samples;
                    bysdf_evaluations += bysdf_evaluations_on_this_thread() - evaluations_before;
                }
            },
            tbb::simple_partitioner());
    });

    RenderResult result;
    result.cancelled = control.cancel.load();
    result.image = film.to_image();
    RenderStats& s = result.stats;
    s.build_seconds = build_seconds_;
    s.render_seconds = seconds_since(start);
    if (denoiser && !result.cancelled) {
        const auto denoise_start = Clock::now();
        denoiser->denoise(result.image, {threads});
        s.denoise_seconds = seconds_since(denoise_start);
    }
    s.samples = uint64_t(width) * height * settings.spp;
    s.rays = rays;
    s.mean_path_length = s.samples ? double(interactions) / double(s.samples) : 0.0;
    s.invalid_samples = invalid;
    s.acceleration_bytes = geometry_->acceleration_bytes();
    for (const YarnSetDesc& y : scene_.yarns) {
        s.control_points += y.curves.point_count();
        s.curves += y.curves.curve_count();
    }
    s.shading_bytes = shader_->memory_bytes();
    s.peak_resident_bytes = peak_resident_bytes();
    s.threads = threads;
    s.hits_near = hits_near;
    s.hits_multi = hits_multi;
    s.hits_far = hits_far;
    s.h_samples = h_samples;
    s.bysdf_evaluations = bysdf_evaluations;
    s.warnings = warnings;
    return result;
}

void Renderer::render_pixel(int px, int py, const RenderSettings& settings, const MultiscaleSelector& multiscale,
                            PixelResult& out, PathTotals& totals) const {
    Vec3 color_sum(0.0f), normal_sum(0.0f), albedo_sum(0.0f), denoising_normal_sum(0.0f);
    double alpha_sum = 0;
    const int first = settings.first_sample;  // sample 0 of this pass sets the per-sample passes
    for (int s = first; s < first + settings.spp; ++s) {
        Rng rng = pixel_sample_rng(settings.seed, uint32_t(px), uint32_t(py), uint32_t(s));
        const float jx = rng.next_float(), jy = rng.next_float();
        Ray ray = camera_.generate_ray(px + jx, py + jy);
        // Multi-scale draws from its own stream, so the path's random numbers (and near-mode
        // images) do not depend on the mode.
        Rng hit_rng = pixel_sample_rng(settings.seed ^ 0x6d756c7469ULL, uint32_t(px), uint32_t(py), uint32_t(s));

        Vec3 radiance(0.0f), throughput(1.0f);
        float alpha = 1.0f;
        float previous_pdf = 0.0f;  // solid-angle pdf of the BSDF sample that made `ray`
        float min_bounce_pdf = std::numeric_limits<float>::infinity();  // path regularisation
        int depth = 0, pass_throughs = 0, light_pass_throughs = 0;
        DenoisingPath features;
        RayCone cone = RayCone::from_camera(ray);
        Vec3 cone_origin = ray.origin;  // where `cone` has its width
        while (depth < settings.max_depth) {
            SurfaceHit hit;
            ++totals.rays;
            const bool hit_surface = geometry_->intersect(ray, hit);
            const float surface_t = hit_surface ? hit.t : ray.tmax;

            // Emitters not in Embree (area and sphere lights) in front of the surface.
            EmitterHit emitter;
            if (lights_->intersect_emitter(ray, surface_t, emitter)) {
                const float w = depth == 0 ? 1.0f : power_heuristic(previous_pdf, emitter.pdf);
                radiance += throughput * emitter.radiance * w;
                // Lights are not surfaces (as in Cycles): the ray goes on to what lies behind,
                // so a light in view or under a BSDF sample hides nothing.
                if (++light_pass_throughs > kMaxPassThroughs) break;
                ray.tmin = emitter.distance * (1 + 1e-5f) + 1e-7f;
                continue;
            }
            if (!hit_surface) {
                if (depth == 0) {
                    if (scene_.film.transparent) alpha = 0.0f;
                    else radiance += lights_->background(ray.direction);
                } else {
                    lights_->for_each_escaped(ray.direction, [&](const EmitterHit& e) {
                        radiance += throughput * e.radiance * power_heuristic(previous_pdf, e.pdf);
                    });
                }
                break;
            }
            if (settings.trace_only) {  // benchmark baseline: traversal alone, no shading
                radiance += Vec3(0.5f);
                ++totals.interactions;
                break;
            }
            if (depth == 0 && pass_throughs == 0) {
                out.depth = std::min(out.depth, camera_.view_depth(hit.position));
                normal_sum += dot(hit.geometric_normal, ray.direction) < 0 ? hit.geometric_normal : -hit.geometric_normal;
                if (s == first && hit.kind == SurfaceKind::Yarn)
                    out.yarn_id = float(yarn_id_base_[hit.object] +
                                        uint32_t(scene_.yarns[hit.object].curves.curve_ids[hit.curve]) + 1);
            }
            // The camera ray (also after passing between plies) keeps its differentials and is
            // shaded by the multi-scale selector; deeper rays shade near.
            MultiscaleHitContext camera_hit;
            if (depth == 0) camera_hit = {&multiscale, hit_rng.next_float(), hit_rng.next_float()};
            const float cone_distance = length(hit.position - cone_origin);
            SurfaceInteraction si =
                shader_->shade(hit, ray, depth == 0 ? &camera_hit : nullptr, cone.width_at(cone_distance));
            if (si.multiscale_hit) {
                ++totals.hits_by_mode[si.multiscale_mode == MultiscaleMode::Far     ? 2
                                      : si.multiscale_mode == MultiscaleMode::Multi ? 1
                                                                                    : 0];
                totals.h_samples += uint64_t(si.h_samples);
            }
            if (si.pass_through) {
                // Between the plies: the ray goes on through the yarn, no scattering.
                if (++pass_throughs > kMaxPassThroughs) break;
                ray.tmax = std::max(0.0f, ray.tmax - dot(si.continue_origin - ray.origin, ray.direction));
                ray.origin = si.continue_origin;
                ray.tmin = 0.0f;
                continue;
            }
            ++totals.interactions;
            if (s == first && depth == 0) {
                out.ply_index = float(si.ply_index);
                if (si.ply_index >= 0) {
                    out.u_ply = si.u_ply;
                    out.v_ply = si.v_ply;
                }
            }
            if (depth > 0) roughen(si.point, regularization_alpha(settings.filter_glossy, min_bounce_pdf));
            const ShadingPoint& sp = si.point;
            const Vec3 wo = -ray.direction;
            features.record(sp, wo, camera_);
            if (sp.holdout) {  // cut out of the image, and black to everything else
                if (depth == 0) alpha = 0.0f;
                break;
            }

            // Next-event estimation.
            LightSample ls;
            const float u_light = rng.next_float();
            const Vec2 u_light2(rng.next_float(), rng.next_float());
            if (lights_->sample(sp.position, u_light, u_light2, ls) && ls.pdf > 0 && !is_black(ls.radiance)) {
                const ShadingPoint::Exit exit = sp.leave(ls.wi);
                const BsdfEvalPdf fp = sp.eval_pdf(wo, ls.wi, exit);  // one evaluation: f and the MIS pdf
                const float cos_i = std::fabs(dot(ls.wi, sp.frame.n));
                if (!is_black(fp.f) && cos_i > 0) {
                    ++totals.rays;
                    const ShadowRay shadow = shadow_ray_to_light(exit.origin, sp.position, ls.wi, ls.distance);
                    if (shadow.empty || !geometry_->occluded(shadow.origin, shadow.direction, 0.0f, shadow.tmax)) {
                        const float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, fp.pdf);
                        radiance += throughput * fp.f * ls.radiance * (cos_i * w / ls.pdf);
                    }
                }
            }

            // Continue the path by sampling the BSDF.
            const float u_lobe = rng.next_float();
            const Vec2 u_dir(rng.next_float(), rng.next_float());
            ShadingPoint::Exit exit;
            const std::optional<BsdfSample> bs = sp.sample(wo, u_lobe, u_dir, exit);
            if (!bs || !(bs->pdf > 0)) break;
            throughput *= bs->f * (std::fabs(dot(bs->wi, sp.frame.n)) / bs->pdf);
            if (is_black(throughput)) break;
            previous_pdf = bs->pdf;
            min_bounce_pdf = std::min(min_bounce_pdf, bs->pdf);
            ++depth;
            if (depth >= kRouletteDepth) {
                const float survive = std::min(0.95f, max_component(throughput));
                if (rng.next_float() >= survive) break;
                throughput = throughput / survive;
            }
            ray = Ray();
            ray.origin = exit.origin;
            ray.direction = bs->wi;
            cone.scatter(cone_distance, hit.kind == SurfaceKind::Yarn && hit.radius > 0 ? 1.0f / hit.radius : 0.0f);
            cone_origin = ray.origin;
        }
        albedo_sum += features.albedo();
        denoising_normal_sum += features.normal();
        if (!is_finite(radiance) || radiance.x < 0 || radiance.y < 0 || radiance.z < 0) {
            ++totals.invalid;
            continue;  // dropped: counts as black
        }
        if (settings.clamp > 0 && max_component(radiance) > settings.clamp)
            radiance = radiance * (settings.clamp / max_component(radiance));
        color_sum += radiance * alpha;
        alpha_sum += alpha;
    }
    const float inv = 1.0f / float(settings.spp);
    out.color = color_sum * inv;
    out.alpha = float(alpha_sum * inv);
    out.denoising_albedo = albedo_sum * inv;
    out.denoising_normal = denoising_normal_sum * inv;
    const float nl = length(normal_sum);
    out.normal = nl > 0 ? normal_sum / nl : Vec3(0.0f);
}

}  // namespace purl
