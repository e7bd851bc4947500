// The harness itself: it must accept a correct sampler and reject near misses.
#include <gtest/gtest.h>

#include "support/chi_square.h"
#include "math/sampling.h"

namespace purl::test {
namespace {

TEST(ChiSquare, GammaQMatchesKnownValues) {
    // Q(1, x) = exp(-x); chi-square with 2 dof at 5.991 has p = 0.05; with 10 dof at 18.307, p = 0.05.
    EXPECT_NEAR(regularized_gamma_q(1.0, 2.0), std::exp(-2.0), 1e-12);
    EXPECT_NEAR(regularized_gamma_q(1.0, 5.991 / 2), 0.05, 1e-4);
    EXPECT_NEAR(regularized_gamma_q(5.0, 18.307 / 2), 0.05, 1e-4);
    EXPECT_NEAR(regularized_gamma_q(200.0, 180.0), 0.9236, 2e-3);
}

TEST(ChiSquare, IntegratesKnownFunctions) {
    const double area = integrate_sphere([](Vec3) { return 1.0; }, 10, 20, 1e-9);
    EXPECT_NEAR(area, 4 * M_PI, 1e-9);
    const double cos_lobe = integrate_sphere([](Vec3 w) { return std::max(0.0f, w.z) * kInvPi; }, 10, 20, 1e-9);
    EXPECT_NEAR(cos_lobe, 1.0, 1e-6);
    // A sharp lobe the adaptive rule must resolve: normalised (n+1)/(2 pi) cos^n.
    const double phong = integrate_sphere(
        [](Vec3 w) { return w.z > 0 ? 201.0 / (2 * M_PI) * std::pow(double(w.z), 200.0) : 0.0; }, 20, 40, 1e-7);
    EXPECT_NEAR(phong, 1.0, 1e-5);
}

TEST(ChiSquare, AcceptsCorrectSampler) {
    const Chi2Result r = chi2_test([](Vec3 u) { return std::optional<Vec3>(sample_cosine_hemisphere({u.y, u.z})); },
                                   [](Vec3 w) { return double(cosine_hemisphere_pdf(w.z)); }, {});
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
}

TEST(ChiSquare, RejectsSlightlyWrongPdf) {
    // Sampling cos^1 but claiming cos^1.05: a 5% shape error must be caught.
    const Chi2Result r = chi2_test(
        [](Vec3 u) { return std::optional<Vec3>(sample_cosine_hemisphere({u.y, u.z})); },
        [](Vec3 w) { return w.z > 0 ? 3.05 / (2 * M_PI) * std::pow(double(w.z), 1.05) : 0.0; }, {});
    EXPECT_FALSE(r.passed) << r.message;
}

TEST(ChiSquare, RejectsMissingMass) {
    // Dropping 2% of samples without the pdf saying so must be caught by the failure cell.
    const Chi2Result r = chi2_test(
        [](Vec3 u) {
            if (u.x < 0.02f) return std::optional<Vec3>();
            return std::optional<Vec3>(sample_cosine_hemisphere({u.y, u.z}));
        },
        [](Vec3 w) { return double(cosine_hemisphere_pdf(w.z)); }, {});
    EXPECT_FALSE(r.passed) << r.message;
}

TEST(ChiSquare, AcceptsAccountedMissingMass) {
    const Chi2Result r = chi2_test(
        [](Vec3 u) {
            if (u.x < 0.25f) return std::optional<Vec3>();
            return std::optional<Vec3>(sample_cosine_hemisphere({u.y, u.z}));
        },
        [](Vec3 w) { return 0.75 * cosine_hemisphere_pdf(w.z); }, {});
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.success_fraction, 0.75, 0.01);
}

}  // namespace
}  // namespace purl::test
