// The placeholder materials: sampling matches pdf, energy stays below 1, values are consistent.
#include <gtest/gtest.h>

#include "bsdf/placeholder.h"
#include "support/chi_square.h"
#include "math/rng.h"

namespace purl::test {
namespace {

// Albedo by quadrature of f cos over the sphere (independent of the sampler).
template <class Model>
double albedo(const Model& m, Vec3 wo) {
    return integrate_sphere([&](Vec3 wi) { return double(average(m.eval(wo, wi))) * std::fabs(wi.z); }, 20, 40, 1e-7);
}

template <class Model>
void expect_sampler_matches_pdf(const Model& m, Vec3 wo, int runs, uint64_t seed) {
    Chi2Options o;
    o.test_count = runs;
    o.seed = seed;
    const Chi2Result r = chi2_test(
        [&](Vec3 u) -> std::optional<Vec3> {
            auto s = m.sample(wo, u.x, {u.y, u.z});
            if (!s) return std::nullopt;
            EXPECT_NEAR(s->pdf, m.pdf(wo, s->wi), 1e-4f * s->pdf);
            EXPECT_NEAR(average(s->f), average(m.eval(wo, s->wi)), 1e-4f * average(s->f) + 1e-7f);
            return s->wi;
        },
        [&](Vec3 wi) { return double(m.pdf(wo, wi)); }, o);
    EXPECT_TRUE(r.passed) << "wo.z " << wo.z << ": " << r.message;
}

TEST(DiffuseBsdf, SamplingAndEnergy) {
    const DiffuseBsdf d{Vec3(1.0f)};
    const Vec3 wo = normalize(Vec3(0.3f, 0.2f, 0.9f));
    expect_sampler_matches_pdf(d, wo, 1, 5);
    EXPECT_NEAR(albedo(d, wo), 1.0, 1e-4);
    EXPECT_TRUE(is_black(d.eval(wo, Vec3(0, 0, -1))));    // one-sided
    EXPECT_FALSE(d.sample(Vec3(0, 0, -1), 0.5f, {0.5f, 0.5f}).has_value());
}

TEST(PlaceholderYarnBsdf, SamplingMatchesPdf) {
    Rng rng(9);
    const int runs = 8;
    for (int k = 0; k < runs; ++k) {
        PlaceholderYarnBsdf m{Vec3(rng.next_float(), rng.next_float(), rng.next_float()),
                              0.25f + 0.75f * rng.next_float(), rng.next_float()};
        const float cos_o = k == 0 ? 0.03f : rng.next_float();
        const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0.0f, cos_o);
        expect_sampler_matches_pdf(m, wo, runs, 200 + k);
    }
}

TEST(PlaceholderYarnBsdf, NeverReflectsMoreThanItReceives) {
    for (float roughness : {0.1f, 0.5f, 1.0f})
        for (float cos_o : {1.0f, 0.5f, 0.1f, 0.02f}) {
            const PlaceholderYarnBsdf m{Vec3(1.0f), roughness, 1.0f};
            const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0.0f, cos_o);
            const double a = albedo(m, wo);
            EXPECT_LE(a, 1.0 + 1e-3) << "roughness " << roughness << " cos_o " << cos_o;
            EXPECT_GT(a, 0.5) << "roughness " << roughness << " cos_o " << cos_o;
        }
}

TEST(PlaceholderYarnBsdf, ParamTableDescribesTheStruct) {
    PlaceholderParams p;
    apply_defaults(p, placeholder_param_table());
    const PlaceholderYarnBsdf m = make_placeholder_bsdf(p);
    EXPECT_FLOAT_EQ(m.color.y, 0.8f);
    EXPECT_FLOAT_EQ(m.roughness, 0.3f);
    EXPECT_FLOAT_EQ(m.specular, 0.5f);
    size_t covered = 0;
    for (const ParamInfo& i : placeholder_param_table()) covered += i.components * sizeof(float);
    EXPECT_EQ(covered, sizeof(PlaceholderParams));
}

}  // namespace
}  // namespace purl::test
