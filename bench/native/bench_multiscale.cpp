// Multi-scale BYSDF against the near field on a straight yarn (radius 1, default description
// and material), camera 0.3 rad off the yarn's normal plane, footprints given in h units
// (2 = one pixel spans the yarn's diameter).
//
//   BM_NearShade        trace_yarn_hit + Bysdf construction: what the renderer pays per near-field hit
//   BM_Build/m/w        MultiscaleBysdf construction (K - 1 virtual implicit queries plus the camera
//                       ray's own; counter K = cells traced), mode m (0 near, 1 multi,
//                       2 far), footprint w / 1000
//   BM_Eval, BM_Sample  one eval / sample of a built model (random directions)
//   BM_Pixel/m/w/k      one camera sample of a pixel w / 1000 wide in h (h0 uniform over the pixel,
//                       position along the yarn uniform over the same width): build the model for
//                       mode m (0 near, 1 multi, 2 far, 3 auto), pass through with pass_fraction, and
//                       estimate (a) a directional light (NEE with a delta light) and (b) a white
//                       environment through BSDF sampling. Counters: the per-sample mean and
//                       relative variance of each, and time_1pct_us, the CPU time this first-hit
//                       estimate needs to reach 1 % relative standard error (relvar / 1e-4 x time
//                       per sample): lower is better; equal-quality speed-up = ratio of these.
//                       k > 0 overrides max_h_samples.
#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <vector>

#include "bsdf/bysdf_params.h"
#include "math/rng.h"
#include "math/sampling.h"
#include "reference/ply_validation.h"
#include "render/multiscale.h"
#include "yarn/yarn_shading_point.h"

namespace purl {
namespace {

constexpr float kPsi = 0.3f;
constexpr int kPrepared = 256;

struct Yarn {
    std::vector<Vec4> points = validation_curve(0.0f);
    CurveFrames frames{CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), false)};
    YarnDescription description = default_yarn_description();
    FiberMaps maps{description};
    BysdfParams params = default_bysdf_params();
    MultiscaleSettings settings = default_multiscale_settings();

    MultiscaleYarn yarn() const { return {&frames, &description, &maps, &params, 7, Vec3(1.0f), {}}; }

    // Camera ray at offset y across the yarn (|y| < 1) entering at height z, with one-pixel
    // differentials `width` apart across the yarn and `width` along it.
    MultiscaleQuery query(float y, float z, float width, MultiscaleMode mode, float u) const {
        MultiscaleQuery q;
        const Vec3 d = normalize(Vec3(-std::cos(kPsi), 0.0f, std::sin(kPsi)));
        q.tube.direction = d;
        q.tube.point = Vec3(std::sqrt(1 - y * y), y, z);
        q.tube.origin = q.tube.point - d * 5.0f;
        const CentrelineProjection p0 = project_to_centreline(frames, q.tube.point, uint32_t(z) - 1, 0.5f);
        q.tube.segment = p0.segment;
        q.tube.t = p0.t;
        q.axis = project_to_centreline(frames, q.tube.point, q.tube.segment, q.tube.t);
        Ray r;
        r.origin = q.tube.origin;
        r.direction = d;
        r.has_differentials = true;
        r.rx_origin = r.origin + Vec3(0, width, 0);
        r.ry_origin = r.origin + cross(d, Vec3(0, 1, 0)) * width;
        r.rx_direction = r.ry_direction = d;
        q.footprint = yarn_footprint(r, q.tube.point, q.axis.point);
        q.mode = mode;
        q.u_strata = u;
        return q;
    }
};

Yarn& yarn() {
    static Yarn y;
    return y;
}

MultiscaleMode mode_of(int64_t m) {
    return m == 0 ? MultiscaleMode::Near : m == 1 ? MultiscaleMode::Multi : m == 2 ? MultiscaleMode::Far : MultiscaleMode::Auto;
}

std::vector<MultiscaleQuery> prepared_queries(float width, MultiscaleMode mode) {
    const Yarn& y = yarn();
    Rng rng(5);
    std::vector<MultiscaleQuery> q;
    for (int i = 0; i < kPrepared; ++i)
        q.push_back(y.query(1.8f * rng.next_float() - 0.9f, 30 + 10 * rng.next_float(), width, mode, rng.next_float()));
    return q;
}

void BM_NearShade(benchmark::State& state) {
    const Yarn& y = yarn();
    const std::vector<MultiscaleQuery> q = prepared_queries(0, MultiscaleMode::Near);
    size_t i = 0;
    for (auto _ : state) {
        const YarnShadingPoint sp = trace_yarn_hit(y.frames, y.description, y.maps, q[i++ % kPrepared].tube, 7);
        const Bysdf b(y.params, {sp.ply_shadowing, sp.fiber_shadowing, std::max(1, sp.plies_crossed), sp.ply_index});
        benchmark::DoNotOptimize(b);
    }
}

void BM_Build(benchmark::State& state) {
    const Yarn& y = yarn();
    const std::vector<MultiscaleQuery> q = prepared_queries(state.range(1) / 1000.0f, mode_of(state.range(0)));
    size_t i = 0;
    double k = 0;
    for (auto _ : state) {
        const MultiscaleBysdf m(y.yarn(), y.settings, q[i++ % kPrepared]);
        k += m.samples();
        benchmark::DoNotOptimize(m);
    }
    state.counters["K"] = k / double(state.iterations());
}

std::vector<MultiscaleBysdf> built_models(const benchmark::State& state) {
    const Yarn& y = yarn();
    std::vector<MultiscaleBysdf> models;
    for (const MultiscaleQuery& q : prepared_queries(state.range(1) / 1000.0f, mode_of(state.range(0)))) {
        MultiscaleBysdf m(y.yarn(), y.settings, q);
        if (!m.empty()) models.push_back(m);
    }
    return models;
}

void BM_Eval(benchmark::State& state) {
    const std::vector<MultiscaleBysdf> models = built_models(state);
    Rng rng(3);
    std::vector<Vec3> dirs;
    for (int i = 0; i < 1024; ++i) dirs.push_back(sample_uniform_sphere({rng.next_float(), rng.next_float()}));
    size_t i = 0;
    for (auto _ : state) {
        const MultiscaleBysdf& m = models[i % models.size()];
        benchmark::DoNotOptimize(m.eval_pdf(m.frame().to_local(dirs[i & 1023]), dirs[(i * 7 + 3) & 1023]));
        ++i;
    }
}

void BM_Sample(benchmark::State& state) {
    const std::vector<MultiscaleBysdf> models = built_models(state);
    Rng rng(4);
    size_t i = 0;
    const Vec3 wo_world = normalize(Vec3(std::cos(kPsi), 0.0f, -std::sin(kPsi)));
    for (auto _ : state) {
        const MultiscaleBysdf& m = models[i++ % models.size()];
        benchmark::DoNotOptimize(m.sample(m.frame().to_local(wo_world), rng.next_float(), {rng.next_float(), rng.next_float()}));
    }
}

void BM_Pixel(benchmark::State& state) {
    Yarn& y = yarn();
    const MultiscaleSettings saved = y.settings;
    if (state.range(2) > 0) y.settings.max_h_samples = float(state.range(2));
    const MultiscaleMode forced = mode_of(state.range(0));
    const float width = state.range(1) / 1000.0f;
    const MultiscaleSelector selector(y.settings);
    const Vec3 wo_world = normalize(Vec3(std::cos(kPsi), 0.0f, -std::sin(kPsi)));
    const Vec3 light = normalize(Vec3(1.0f, 0.5f, 0.6f));
    Rng rng(11);
    double sum_d = 0, sum_d2 = 0, sum_e = 0, sum_e2 = 0, k_sum = 0;
    const std::clock_t start = std::clock();  // CPU time: the machine may be shared
    for (auto _ : state) {
        // h0 uniform over the pixel (cut to the yarn: camera samples that miss it are the same
        // background in every mode), along the yarn uniform over a square pixel.
        const float half = std::min(0.5f * width, 1.0f);
        const float h0 = clamp((2 * rng.next_float() - 1) * half, -0.9999f, 0.9999f);
        const float z = 35 + width * rng.next_float();
        MultiscaleQuery q = y.query(h0, z, width, MultiscaleMode::Near, rng.next_float());
        q.mode = forced == MultiscaleMode::Auto ? selector.choose(q.footprint, y.description) : forced;
        const MultiscaleBysdf m(y.yarn(), y.settings, q);
        k_sum += m.samples();
        float direct = 0, env = 0;
        const float u_pass = rng.next_float(), u_lobe = rng.next_float();
        const Vec2 u_dir(rng.next_float(), rng.next_float());
        if (!m.empty() && u_pass >= m.pass_fraction()) {
            const Vec3 wo = m.frame().to_local(wo_world), wi = m.frame().to_local(light);
            direct = average(m.eval(wo, wi)) * std::fabs(wi.z);
            if (const auto s = m.sample(wo, u_lobe, u_dir)) env = average(s->weight());
        }
        sum_d += direct;
        sum_d2 += double(direct) * direct;
        sum_e += env;
        sum_e2 += double(env) * env;
    }
    const double seconds = double(std::clock() - start) / CLOCKS_PER_SEC;
    const double n = double(state.iterations());
    const double mean_d = sum_d / n, mean_e = sum_e / n;
    const double relvar_d = (sum_d2 / n - mean_d * mean_d) / std::max(mean_d * mean_d, 1e-30);
    const double relvar_e = (sum_e2 / n - mean_e * mean_e) / std::max(mean_e * mean_e, 1e-30);
    const double us_per_sample = 1e6 * seconds / n;
    state.counters["K"] = k_sum / n;
    state.counters["direct_mean"] = mean_d;
    state.counters["direct_relvar"] = relvar_d;
    state.counters["direct_time_1pct_us"] = relvar_d / 1e-4 * us_per_sample;
    state.counters["env_mean"] = mean_e;
    state.counters["env_relvar"] = relvar_e;
    state.counters["env_time_1pct_us"] = relvar_e / 1e-4 * us_per_sample;
    y.settings = saved;
}

void model_arguments(benchmark::internal::Benchmark* b) {
    b->Args({0, 0});
    for (int w : {100, 250, 500, 1000}) b->Args({1, w});
    b->Args({2, 2000});
}

void pixel_arguments(benchmark::internal::Benchmark* b) {
    for (int w : {50, 250, 500, 1000, 2000, 4000})
        for (int m : {0, 1, 2, 3}) b->Args({m, w, 0});
    for (int k : {3, 5, 7}) b->Args({1, 2000, k});
    b->Iterations(20000);
}

BENCHMARK(BM_NearShade);
BENCHMARK(BM_Build)->Apply(model_arguments);
BENCHMARK(BM_Eval)->Apply(model_arguments);
BENCHMARK(BM_Sample)->Apply(model_arguments);
BENCHMARK(BM_Pixel)->Apply(pixel_arguments);

}  // namespace
}  // namespace purl

BENCHMARK_MAIN();
