// Fuzzed evaluations and samples: no NaN, Inf or negative value for any input, including
// grazing and exactly tangent directions, wi == wo, wi == -wo, the poles, slightly
// non-unit vectors, and extreme roughness, eta, extinction, chord and ply counts.
#include <gtest/gtest.h>

#include <cstdio>

#include "random_bysdf.h"

namespace purl::test {
namespace {

float pick(Rng& rng, std::initializer_list<float> values) {
    return values.begin()[std::min<size_t>(values.size() - 1, size_t(rng.next_float() * values.size()))];
}

BysdfParams extreme_params(Rng& rng) {
    BysdfParams p = random_bysdf_params(rng);
    if (rng.next_float() < 0.5f) {
        p.specular_roughness_along = pick(rng, {0.0f, 1e-6f, 1e-3f, 0.01f, 1.0f, 5.0f});
        p.specular_roughness_across = pick(rng, {0.0f, 1e-6f, 1e-3f, 0.01f, 1.0f, 5.0f});
        p.transmission_roughness = pick(rng, {0.0f, 1e-6f, 1e-3f, 0.01f, 1.0f, 5.0f});
    }
    if (rng.next_float() < 0.3f) p.eta = pick(rng, {1.0f, 1.0001f, 1.05f, 3.0f, 10.0f, 0.5f});
    if (rng.next_float() < 0.3f) {
        p.sigma_t_specular = pick(rng, {0.0f, 1e-6f, 1000.0f, 1e30f, INFINITY});
        p.sigma_t_body = pick(rng, {0.0f, 1e-6f, 1000.0f, 1e30f, INFINITY});
    }
    if (rng.next_float() < 0.2f) p.body_share = pick(rng, {0.0f, 1.0f});
    if (rng.next_float() < 0.2f) p.body_reflection_share = pick(rng, {0.0f, 1.0f});
    if (rng.next_float() < 0.1f) p.ply_color_count = pick(rng, {0.0f, 13.0f, -1.0f});
    return p;
}

BysdfShadingPoint extreme_point(Rng& rng) {
    BysdfShadingPoint sp = random_shading_point(rng);
    if (rng.next_float() < 0.2f) sp.plies_crossed = int(pick(rng, {0.0f, -3.0f, 12.0f, 1e6f}));
    if (rng.next_float() < 0.2f) sp.ply_index = int(pick(rng, {-7.0f, 11.0f, 1e6f}));
    if (rng.next_float() < 0.2f) sp.ply_shadow = pick(rng, {0.0f, 1.0f, -1.0f, 2.0f});
    return sp;
}

Vec3 fuzz_direction(Rng& rng, Vec3 other) {
    const float kind = rng.next_float();
    const float tiny = pick(rng, {0.0f, 1e-30f, 1e-12f, 1e-7f, 1e-6f, 2e-6f, 1e-4f});
    const float sign = rng.next_float() < 0.5f ? -1.0f : 1.0f;
    if (kind < 0.4f) return direction_with_cos(rng, 2 * rng.next_float() - 1);
    if (kind < 0.55f) return direction_with_cos(rng, sign * tiny);                   // grazing
    if (kind < 0.62f) return other;                                                   // wi == wo
    if (kind < 0.69f) return -other;                                                  // wi == -wo
    if (kind < 0.74f) return {other.x, other.y, -other.z};                            // mirror
    if (kind < 0.80f) return {-other.x, -other.y, other.z};                           // specular reflection
    if (kind < 0.86f) return pick(rng, {1.0f, -1.0f}) * Vec3(0, 0, 1);                // poles
    if (kind < 0.90f) return Vec3(sign, 0, 0);                                        // along the tangent
    if (kind < 0.95f) return direction_with_cos(rng, 2 * rng.next_float() - 1) * (1 + sign * 1e-4f);  // not unit
    return normalize(Vec3(sign * tiny, tiny, 1.0f - tiny));                            // near-pole
}

bool good(float v) { return std::isfinite(v) && v >= 0; }
bool good(Vec3 v) { return good(v.x) && good(v.y) && good(v.z); }

struct FuzzReport {
    int64_t calls = 0, bad = 0, samples_returned = 0;
};

FuzzReport fuzz(int64_t iterations, uint64_t seed) {
    Rng rng(seed);
    FuzzReport report;
    BysdfParams p = extreme_params(rng);
    BysdfShadingPoint sp = extreme_point(rng);
    Bysdf m(p, sp);
    for (int64_t i = 0; i < iterations; ++i) {
        if ((i & 63) == 0) {  // a new material and hit every 64 iterations
            p = extreme_params(rng);
            sp = extreme_point(rng);
            m = Bysdf(p, sp);
        }
        const Vec3 wo = fuzz_direction(rng, direction_with_cos(rng, 2 * rng.next_float() - 1));
        const Vec3 wi = fuzz_direction(rng, wo);
        const float chord = pick(rng, {0.0f, 1e-30f, 0.5f, 2.0f, 1e30f, INFINITY});
        const BsdfEvalPdf ep = m.eval_pdf(wo, wi, {chord});
        const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        report.calls += 2;
        bool ok = good(ep.f) && good(ep.pdf);
        if (s) {
            ++report.samples_returned;
            ok = ok && good(s->f) && good(s->pdf) && s->pdf > 0 && is_finite(s->wi) && good(s->weight()) &&
                 std::fabs(length(s->wi) - 1) < 1e-3f;
        }
        if (!ok) {
            if (report.bad < 5)
                std::printf("bad: wo (%g %g %g) wi (%g %g %g) chord %g -> f %g pdf %g\n", wo.x, wo.y, wo.z, wi.x, wi.y,
                            wi.z, chord, ep.f.x, ep.pdf);
            ++report.bad;
        }
    }
    return report;
}

TEST(BysdfFuzz, NoNanInfOrNegativeInAMillionCalls) {
    const FuzzReport r = fuzz(500000, 1);
    std::printf("fuzz: %lld calls (eval_pdf + sample), %lld samples returned, %lld bad\n", (long long)r.calls,
                (long long)r.samples_returned, (long long)r.bad);
    EXPECT_EQ(r.bad, 0);
    EXPECT_GT(r.samples_returned, 100000);  // the fuzz must not only exercise the early exits
}

// The full 1e8: run with --gtest_also_run_disabled_tests --gtest_filter='*Fuzz*'.
TEST(BysdfFuzz, DISABLED_NoNanInfOrNegativeInAHundredMillionCalls) {
    const FuzzReport r = fuzz(50000000, 2);
    std::printf("fuzz: %lld calls (eval_pdf + sample), %lld samples returned, %lld bad\n", (long long)r.calls,
                (long long)r.samples_returned, (long long)r.bad);
    EXPECT_EQ(r.bad, 0);
}

}  // namespace
}  // namespace purl::test
