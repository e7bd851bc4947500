// GGX distribution, visible-normal sampling, Fresnel and Lommel-Seeliger building blocks.
#include <gtest/gtest.h>

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/lommel_seeliger.h"
#include "support/chi_square.h"
#include "math/rng.h"

namespace purl::test {
namespace {

TEST(Fresnel, KnownValues) {
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);        // ((eta-1)/(eta+1))^2
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f), 0.0f, 1e-7f);
    EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);         // grazing
    EXPECT_EQ(fresnel_dielectric(-0.2f, 1.5f), 1.0f);                 // total internal reflection
    EXPECT_NEAR(fresnel_dielectric(-1.0f, 1.5f), 0.04f, 1e-6f);       // from inside, normal incidence
    // 45 degrees, eta 1.5: Rs = 0.0920, Rp = 0.0085 -> 0.0502.
    EXPECT_NEAR(fresnel_dielectric(std::sqrt(0.5f), 1.5f), 0.0502f, 2e-4f);
    EXPECT_NEAR(fresnel_schlick(0.04f, 1.0f), 0.04f, 1e-7f);
    EXPECT_NEAR(fresnel_schlick(0.04f, 0.0f), 1.0f, 1e-7f);
}

TEST(Ggx, NormalDistributionProjectsToOne) {
    // Integral of D(h) cos theta_h over the hemisphere is 1, isotropic and anisotropic.
    for (Ggx g : {Ggx{0.5f, 0.5f}, Ggx{0.1f, 0.4f}, Ggx{1.0f, 0.05f}}) {
        const double v = integrate_sphere([&](Vec3 h) { return double(g.d(h)) * std::max(0.0f, h.z); }, 20, 40, 1e-8);
        EXPECT_NEAR(v, 1.0, 2e-4) << g.alpha_x << " " << g.alpha_y;
    }
}

TEST(Ggx, VisibleNormalsIntegrateToOne) {
    Rng rng(3);
    for (int k = 0; k < 6; ++k) {
        const Ggx g{0.05f + rng.next_float(), 0.05f + rng.next_float()};
        const float cos_o = k == 0 ? 0.02f : rng.next_float();
        const float s = std::sqrt(1 - cos_o * cos_o), phi = 6.283f * rng.next_float();
        const Vec3 wo(s * std::cos(phi), s * std::sin(phi), cos_o);
        const double v = integrate_sphere([&](Vec3 h) { return double(g.visible_normal_pdf(wo, h)); }, 20, 40, 1e-8);
        EXPECT_NEAR(v, 1.0, 1e-3) << "alpha " << g.alpha_x << "," << g.alpha_y << " cos_o " << cos_o;
    }
}

TEST(Ggx, VisibleNormalSamplingMatchesPdf) {
    Rng rng(11);
    const int runs = 8;
    for (int k = 0; k < runs; ++k) {
        const Ggx g{0.05f + rng.next_float(), 0.05f + rng.next_float()};
        const float cos_o = k == 0 ? 0.01f : rng.next_float();
        const float s = std::sqrt(1 - cos_o * cos_o), phi = 6.283f * rng.next_float();
        const Vec3 wo(s * std::cos(phi), s * std::sin(phi), cos_o);
        Chi2Options o;
        o.test_count = runs;
        o.seed = 100 + k;
        const Chi2Result r =
            chi2_test([&](Vec3 u) { return std::optional<Vec3>(g.sample_visible_normal(wo, {u.y, u.z})); },
                      [&](Vec3 h) { return double(g.visible_normal_pdf(wo, h)); }, o);
        EXPECT_TRUE(r.passed) << "alpha " << g.alpha_x << "," << g.alpha_y << " wo.z " << wo.z << ": " << r.message;
    }
}

TEST(Ggx, RefractionObeysSnell) {
    const Vec3 h(0, 0, 1), w = normalize(Vec3(0.6f, 0.0f, 0.8f));
    Vec3 t;
    ASSERT_TRUE(refract(w, h, 1.5f, t));
    EXPECT_NEAR(length(t), 1.0f, 1e-6f);
    EXPECT_NEAR(-t.x * 1.5f, w.x, 1e-6f);  // sin_t eta = sin_i, opposite side of h
    EXPECT_LT(t.z, 0.0f);
    EXPECT_FALSE(refract(w, h, 0.5f, t));  // total internal reflection from the dense side
}

TEST(LommelSeeliger, AlbedoMatchesQuadrature) {
    for (float mu : {1.0f, 0.5f, 0.1f, 0.01f}) {
        const double v = integrate_sphere(
            [&](Vec3 w) { return w.z > 0 ? double(lommel_seeliger(mu, w.z)) * w.z : 0.0; }, 20, 40, 1e-9);
        EXPECT_NEAR(v, lommel_seeliger_albedo(mu), 1e-5) << mu;
    }
    EXPECT_NEAR(lommel_seeliger_albedo(1.0f), 0.5 * (1 - std::log(2.0)), 1e-6);
    EXPECT_EQ(lommel_seeliger_albedo(0.0f), 0.5f);
}

}  // namespace
}  // namespace purl::test
