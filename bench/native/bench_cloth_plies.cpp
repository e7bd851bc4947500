// Implicit plies against explicit plies inside whole cloth: the camera rays of the benchmark
// scenes (bench/scenes), traced against every yarn of the garment, not one isolated yarn
// (bench_implicit_ply measures that easier case for Embree).
//
//   BM_ClothTube      Embree: the camera ray against the yarn tubes of the whole cloth
//   BM_ClothQuery     the implicit query at that tube hit (plies + fiber maps), exact method
//   BM_ClothLocal     the same query with the local method
//   BM_ClothCircular  the same query with the circular cross-section (one circle per ply, no search)
//   BM_ClothFirstPly  the implicit pipeline to the first ply hit: tube trace, query, and on a
//                     pass-through the next tube trace from the exit, as the renderer does
//   BM_ClothExplicit  Embree: the same ray against every ply of the cloth as its own curve
//                     (make_explicit_scene, the renderer's "ply" model): the first ply hit
//   BM_ClothShared    a lower bound of what any implicit query must do besides its ply search:
//                     project the tube hit onto the centre-line and shade the ply hit the exact
//                     query found (fiber maps, shading frame); the hit's own frame and
//                     coordinates are left out
//   BM_ClothToShadingImplicit / BM_ClothToShadingExplicit  the renderer's way from the camera
//                     ray to its first scattering point, near field: Embree against the tubes
//                     and SurfaceShader::shade (the query, on through pass-throughs), or Embree
//                     against the explicit plies and the same shader on the ply hit (the ply's
//                     frame, its yarn cross-section, fiber maps)
// Argument: scene (0 glove_close, 1 glove_far, 2 knit_tube). Rays: camera rays through random
// film positions that meet a yarn tube, prepared outside the timed loop. Counters: Embree bytes
// of each scene and the share of queries that pass between the plies.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "math/rng.h"
#include "reference/explicit_models.h"
#include "reference/explicit_sampling.h"
#include "render/camera.h"
#include "render/shading.h"
#include "scene/embree_scene.h"
#include "scene/scene_json.h"
#include "yarn/yarn_shading_point.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

constexpr int kRays = 1024;
constexpr int kMaxPassThroughs = 8;
const char* const kScenes[] = {"glove_close", "glove_far", "knit_tube"};

struct ClothSetup {
    SceneDesc scene, explicit_scene;
    std::unique_ptr<EmbreeScene> tubes, plies;
    std::vector<std::vector<CurveFrames>> frames;  // per yarn set, per curve
    std::vector<std::vector<YarnTwist>> twists;    // the same, kept per curve as the renderer does
    std::vector<std::unique_ptr<FiberMaps>> maps;  // per yarn set
    std::vector<Ray> rays;
    std::vector<SurfaceHit> hits;  // each ray's tube hit
    std::vector<PlyHit> ply_hits;  // the exact query's ply hit for each
    std::unique_ptr<SurfaceShader> tube_shader, ply_shader;

    explicit ClothSetup(const std::string& name)
        : scene(load_scene_file(std::string(PURL_SOURCE_DIR) + "/bench/scenes/" + name + ".json")),
          explicit_scene(make_explicit_scene(scene, YarnModel::Ply)) {
        tubes = std::make_unique<EmbreeScene>(scene);
        plies = std::make_unique<EmbreeScene>(explicit_scene);
        for (const YarnSetDesc& set : scene.yarns) {
            frames.push_back(yarn_set_frames(set.curves));
            twists.emplace_back();
            for (const CurveFrames& f : frames.back()) twists.back().push_back(yarn_twist(f, set.material.yarn));
            maps.push_back(std::make_unique<FiberMaps>(set.material.yarn));
        }
        const Camera camera(scene.camera, scene.film);
        Rng rng(3, 17);
        for (int tries = 0; static_cast<int>(rays.size()) < kRays && tries < 200 * kRays; ++tries) {
            const Ray ray = camera.generate_ray(rng.next_float() * scene.film.width, rng.next_float() * scene.film.height);
            SurfaceHit hit;
            if (!tubes->intersect(ray, hit) || hit.kind != SurfaceKind::Yarn) continue;
            rays.push_back(ray);
            hits.push_back(hit);
            const YarnTubeHit tube_hit{ray.origin, ray.direction, hit.position, hit.segment, hit.u};
            ply_hits.push_back(trace_plies({frames[hit.object][hit.curve], scene.yarns[hit.object].material.yarn,
                                            twists[hit.object][hit.curve], tube_hit}));
        }
        tube_shader = std::make_unique<SurfaceShader>(scene);
        ply_shader = std::make_unique<SurfaceShader>(explicit_scene);
    }

    // The renderer's first scattering point of a camera ray, near field; false when it leaves.
    bool to_shading(Ray ray, bool explicit_plies) const {
        const EmbreeScene& geometry = explicit_plies ? *plies : *tubes;
        const SurfaceShader& shader = explicit_plies ? *ply_shader : *tube_shader;
        for (int k = 0; k <= kMaxPassThroughs; ++k) {
            SurfaceHit hit;
            if (!geometry.intersect(ray, hit)) return false;
            const SurfaceInteraction s = shader.shade(hit, ray);
            if (!s.pass_through) {
                benchmark::DoNotOptimize(s);
                return true;
            }
            continue_past(ray, hit, s.continue_distance);
        }
        return false;
    }

    YarnShadingPoint query(const Ray& ray, const SurfaceHit& hit, PlyCrossSection method) const {
        PlyTraceOptions options;
        options.cross_section = method;
        const YarnTubeHit tube_hit{ray.origin, ray.direction, hit.position, hit.segment, hit.u};
        return trace_yarn_hit(frames[hit.object][hit.curve], scene.yarns[hit.object].material.yarn,
                              twists[hit.object][hit.curve], *maps[hit.object], tube_hit, hit.curve, options);
    }

    // A ray that passed between the plies goes on from where it leaves the tube, as the renderer's does.
    static void continue_past(Ray& ray, const SurfaceHit& hit, float exit_distance) {
        const float advance = hit.t + exit_distance + ray_offset(hit.position, hit.radius);
        ray.origin = ray.at(advance);
        ray.tmax = std::max(0.0f, ray.tmax - advance);
    }

    // The renderer's way to the first ply: through the yarns the ray passes between plies of.
    bool first_ply(Ray ray) const {
        for (int k = 0; k <= kMaxPassThroughs; ++k) {
            SurfaceHit hit;
            if (!tubes->intersect(ray, hit)) return false;
            if (hit.kind != SurfaceKind::Yarn) return true;
            const YarnShadingPoint y = query(ray, hit, PlyCrossSection::elliptical);
            if (y.hit) return true;
            continue_past(ray, hit, y.exit_distance);
        }
        return false;
    }
};

ClothSetup& setup(int index) {
    static std::map<int, std::unique_ptr<ClothSetup>> cache;
    auto& s = cache[index];
    if (!s) s = std::make_unique<ClothSetup>(kScenes[index]);
    return *s;
}

void label(benchmark::State& state, const ClothSetup& s) {
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["tube_bytes"] = static_cast<double>(s.tubes->acceleration_bytes());
    state.counters["ply_bytes"] = static_cast<double>(s.plies->acceleration_bytes());
}

// Embree against the tubes or against the explicit plies, the same rays.
void embree_trace(benchmark::State& state, bool explicit_plies) {
    ClothSetup& s = setup(static_cast<int>(state.range(0)));
    const EmbreeScene& scene = explicit_plies ? *s.plies : *s.tubes;
    size_t i = 0;
    for (auto _ : state) {
        SurfaceHit hit;
        benchmark::DoNotOptimize(scene.intersect(s.rays[i++ % s.rays.size()], hit));
    }
    label(state, s);
}
void BM_ClothTube(benchmark::State& state) { embree_trace(state, false); }
void BM_ClothExplicit(benchmark::State& state) { embree_trace(state, true); }

void cloth_query(benchmark::State& state, PlyCrossSection method) {
    ClothSetup& s = setup(static_cast<int>(state.range(0)));
    size_t i = 0, pass_throughs = 0;
    for (auto _ : state) {
        const size_t k = i++ % s.rays.size();
        const YarnShadingPoint y = s.query(s.rays[k], s.hits[k], method);
        pass_throughs += !y.hit;
        benchmark::DoNotOptimize(y);
    }
    label(state, s);
    state.counters["pass_through"] = static_cast<double>(pass_throughs) / std::max<size_t>(i, 1);
}
void BM_ClothQuery(benchmark::State& state) { cloth_query(state, PlyCrossSection::elliptical); }
void BM_ClothLocal(benchmark::State& state) { cloth_query(state, PlyCrossSection::local); }
void BM_ClothCircular(benchmark::State& state) { cloth_query(state, PlyCrossSection::circular); }

void BM_ClothFirstPly(benchmark::State& state) {
    ClothSetup& s = setup(static_cast<int>(state.range(0)));
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(s.first_ply(s.rays[i++ % s.rays.size()]));
    label(state, s);
}

void BM_ClothShared(benchmark::State& state) {
    ClothSetup& s = setup(static_cast<int>(state.range(0)));
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ % s.rays.size();
        const SurfaceHit& hit = s.hits[k];
        const CurveFrames& frames = s.frames[hit.object][hit.curve];
        const YarnDescription& yarn = s.scene.yarns[hit.object].material.yarn;
        benchmark::DoNotOptimize(project_to_centreline(frames, hit.position, hit.segment, hit.u));
        const YarnTwist& twist = s.twists[hit.object][hit.curve];
        benchmark::DoNotOptimize(shade_ply_hit(s.ply_hits[k], frames, yarn, twist, *s.maps[hit.object], hit.curve));
    }
    label(state, s);
}

void to_shading(benchmark::State& state, bool explicit_plies) {
    ClothSetup& s = setup(static_cast<int>(state.range(0)));
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(s.to_shading(s.rays[i++ % s.rays.size()], explicit_plies));
    label(state, s);
}
void BM_ClothToShadingImplicit(benchmark::State& state) { to_shading(state, false); }
void BM_ClothToShadingExplicit(benchmark::State& state) { to_shading(state, true); }

BENCHMARK(BM_ClothTube)->DenseRange(0, 2);
BENCHMARK(BM_ClothQuery)->DenseRange(0, 2);
BENCHMARK(BM_ClothLocal)->DenseRange(0, 2);
BENCHMARK(BM_ClothCircular)->DenseRange(0, 2);
BENCHMARK(BM_ClothFirstPly)->DenseRange(0, 2);
BENCHMARK(BM_ClothExplicit)->DenseRange(0, 2);
BENCHMARK(BM_ClothShared)->DenseRange(0, 2);
BENCHMARK(BM_ClothToShadingImplicit)->DenseRange(0, 2);
BENCHMARK(BM_ClothToShadingExplicit)->DenseRange(0, 2);

}  // namespace
}  // namespace purl

BENCHMARK_MAIN();
