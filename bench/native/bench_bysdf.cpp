// Cost per call of the BYSDF and the placeholder materials: eval, pdf and sample on
// random direction pairs (prepared outside the timed loop).
#include <benchmark/benchmark.h>

#include <vector>

#include "bsdf/bysdf.h"
#include "bsdf/placeholder.h"
#include "math/rng.h"
#include "math/sampling.h"

namespace purl {
namespace {

constexpr int kPairs = 4096;

struct Inputs {
    std::vector<Vec3> wo, wi, u;
    Inputs() {
        Rng rng(7);
        for (int i = 0; i < kPairs; ++i) {
            Vec3 o = sample_uniform_sphere({rng.next_float(), rng.next_float()});
            if (o.z < 0) o.z = -o.z;  // viewer side
            wo.push_back(o);
            wi.push_back(sample_uniform_sphere({rng.next_float(), rng.next_float()}));
            u.push_back({rng.next_float(), rng.next_float(), rng.next_float()});
        }
    }
};
const Inputs& inputs() {
    static const Inputs in;
    return in;
}

Bysdf default_bysdf() {
    BysdfShadingPoint sp;
    sp.plies_crossed = 3;
    sp.ply_shadow = 0.8f;
    sp.fiber_shadow = 0.7f;
    return Bysdf(default_bysdf_params(), sp);
}

template <class Model>
void run_eval(benchmark::State& state, const Model& m) {
    const Inputs& in = inputs();
    int i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(m.eval(in.wo[i], in.wi[i]));
        i = (i + 1) & (kPairs - 1);
    }
}
template <class Model>
void run_pdf(benchmark::State& state, const Model& m) {
    const Inputs& in = inputs();
    int i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(m.pdf(in.wo[i], in.wi[i]));
        i = (i + 1) & (kPairs - 1);
    }
}
template <class Model>
void run_sample(benchmark::State& state, const Model& m) {
    const Inputs& in = inputs();
    int i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(m.sample(in.wo[i], in.u[i].x, {in.u[i].y, in.u[i].z}));
        i = (i + 1) & (kPairs - 1);
    }
}

void BysdfEval(benchmark::State& s) { run_eval(s, default_bysdf()); }
void BysdfPdf(benchmark::State& s) { run_pdf(s, default_bysdf()); }
void BysdfSample(benchmark::State& s) { run_sample(s, default_bysdf()); }
void BysdfConstruct(benchmark::State& state) {
    const BysdfParams p = default_bysdf_params();
    BysdfShadingPoint sp;
    for (auto _ : state) {
        sp.ply_index = (sp.ply_index + 1) & 7;
        benchmark::DoNotOptimize(Bysdf(p, sp));
    }
}
void PlaceholderEval(benchmark::State& s) { run_eval(s, PlaceholderYarnBsdf{}); }
void PlaceholderSample(benchmark::State& s) { run_sample(s, PlaceholderYarnBsdf{}); }
void DiffuseEval(benchmark::State& s) { run_eval(s, DiffuseBsdf{}); }
void DiffuseSample(benchmark::State& s) { run_sample(s, DiffuseBsdf{}); }

BENCHMARK(BysdfEval);
BENCHMARK(BysdfPdf);
BENCHMARK(BysdfSample);
BENCHMARK(BysdfConstruct);
BENCHMARK(PlaceholderEval);
BENCHMARK(PlaceholderSample);
BENCHMARK(DiffuseEval);
BENCHMARK(DiffuseSample);

}  // namespace
}  // namespace purl

BENCHMARK_MAIN();
