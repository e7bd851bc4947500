// Sampling against pdf for the near, multi and far models (mixture and aggregate), with the
// shared chi-square harness; sample records against eval/pdf; and the mixture's albedo
// against its components' own albedos (which catches a wrong cosine between frames).
#include <gtest/gtest.h>

#include <cstdio>

#include "support/chi_square.h"
#include "math/rng.h"
#include "multiscale_fixture.h"

namespace purl::test {
namespace {

struct Case {
    const char* name;
    MultiscaleMode mode;
    MultiscaleAggregation aggregation;
    float y, psi, width, u;
    Vec3 wo;  // in the model's reference frame: (x, y, z) normalised
};

TEST(MultiscaleSampling, ChiSquareNearMultiFar) {
    StraightYarn s;
    s.params.specular_roughness_along = 0.08f;  // sharp lobes: the mixture's structure shows
    s.params.specular_roughness_across = 0.15f;
    s.params.transmission_roughness = 0.3f;
    s.settings.roughness_c = 64;
    const std::vector<Case> cases = {
        {"near", MultiscaleMode::Near, MultiscaleAggregation::Mixture, 0.3f, 0.2f, 0.0f, 0.5f, {0.2f, 0.1f, 0.9f}},
        {"multi", MultiscaleMode::Multi, MultiscaleAggregation::Mixture, -0.2f, 0.0f, 0.5f, 0.4f, {0.3f, -0.2f, 0.8f}},
        {"multi grazing", MultiscaleMode::Multi, MultiscaleAggregation::Mixture, 0.7f, 0.6f, 0.3f, 0.9f, {0.9f, 0.2f, 0.05f}},
        {"far", MultiscaleMode::Far, MultiscaleAggregation::Mixture, 0.0f, 0.3f, 0.0f, 0.2f, {-0.1f, 0.4f, 0.6f}},
        {"far back-facing", MultiscaleMode::Far, MultiscaleAggregation::Mixture, 0.5f, 0.0f, 0.0f, 0.6f, {0.3f, 0.3f, -0.5f}},
        {"far aggregate", MultiscaleMode::Far, MultiscaleAggregation::Aggregate, 0.0f, 0.0f, 0.0f, 0.3f, {0.1f, 0.2f, 0.7f}},
    };
    int failures = 0;
    for (size_t k = 0; k < cases.size(); ++k) {
        const Case& c = cases[k];
        MultiscaleSettings settings = s.settings;
        settings.aggregation = c.aggregation;
        const MultiscaleBysdf m(s.yarn(), settings, s.query(c.y, c.psi, 38.3f, c.width, c.mode, c.u));
        ASSERT_FALSE(m.empty()) << c.name;
        if (c.mode == MultiscaleMode::Multi) {
            EXPECT_GT(m.components(), 1) << c.name;
        }
        if (c.mode == MultiscaleMode::Far && c.aggregation == MultiscaleAggregation::Mixture) {
            EXPECT_GT(m.components(), 8) << c.name;
        }
        const Vec3 wo = normalize(c.wo);
        Chi2Options o;
        o.samples = 150000;
        o.test_count = static_cast<int>(cases.size());
        o.seed = 500 + k;
        int mismatches = 0;
        const Chi2Result r = chi2_model(m, wo, o, mismatches);
        EXPECT_EQ(mismatches, 0) << c.name;
        EXPECT_TRUE(r.passed) << c.name << " (" << m.components() << " components)\n" << r.message;
        if (!r.passed) ++failures;
        std::printf("%-16s K %2d components %2d  chi2 %.1f dof %d p %.3f  pdf mass %.4f\n", c.name, m.samples(),
                    m.components(), r.statistic, r.dof, r.p_value, r.pdf_integral);
    }
    EXPECT_EQ(failures, 0);
}

TEST(MultiscaleSampling, MixtureAlbedoIsTheMeanOfItsComponents) {
    // White, non-absorbing yarn: the albedo of the mixture, estimated through its own sampler
    // in the reference frame, must equal the weighted mean of each h's BYSDF albedo estimated
    // in that h's own frame. Dropping the cos_k / cos_ref factor moves it by ~10-40 %.
    StraightYarn s;
    s.params.body_reflection_albedo = Vec3(1.0f);
    s.params.body_transmission_albedo = Vec3(1.0f);
    s.params.sigma_t_body = s.params.sigma_t_specular = 0;
    // A component's own sample() knows nothing of the plies its rays cross; the mixture's
    // bookkeeping is what is checked here, so the paper's crossing (none in the lobes).
    s.params.ply_crossing = 0;
    for (float psi : {0.0f, 0.7f}) {
        const MultiscaleBysdf m(s.yarn(), s.settings, s.query(0.1f, psi, 38.3f, 0.0f, MultiscaleMode::Far, 0.25f));
        ASSERT_GT(m.components(), 8);
        const Vec3 wo_world = -StraightYarn::direction(psi);
        const Vec3 wo = m.frame().to_local(wo_world);
        constexpr int kN = 200000;
        Rng rng(9, uint64_t(psi * 100));
        double mixture = 0;
        for (int i = 0; i < kN; ++i) {
            const auto smp = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
            if (smp) mixture += average(smp->weight());
        }
        mixture /= kN;
        double components = 0;
        for (int k = 0; k < m.components(); ++k) {
            const MultiscaleBysdf::Component& c = m.component(k);
            const Vec3 wo_k = c.frame.to_local(wo);
            double a = 0;
            for (int i = 0; i < kN / 8; ++i) {
                const auto smp = c.bsdf->sample(wo_k, rng.next_float(), {rng.next_float(), rng.next_float()});
                if (smp) a += average(smp->weight());
            }
            components += c.weight * a / (kN / 8);
        }
        std::printf("psi %.1f: mixture albedo %.4f, mean of component albedos %.4f\n", psi, mixture, components);
        EXPECT_NEAR(mixture, components, 0.01);
        EXPECT_LE(mixture, 1.0 + 0.01);
        EXPECT_GT(mixture, 0.5);
    }
}

TEST(MultiscaleSampling, NonFiniteOrDegenerateInputsStayFinite) {
    const StraightYarn s;
    const MultiscaleBysdf m(s.yarn(), s.settings, s.query(0.1f, 0.0f, 38.3f, 0.0f, MultiscaleMode::Far, 0.5f));
    Rng rng(3);
    const Vec3 dirs[] = {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 1e-9f), Vec3(0.0f)};
    for (Vec3 wo : dirs)
        for (Vec3 wi : dirs) {
            const BsdfEvalPdf e = m.eval_pdf(wo, wi);
            EXPECT_TRUE(is_finite(e.f) && std::isfinite(e.pdf));
            EXPECT_GE(e.pdf, 0.0f);
            const auto smp = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
            if (smp) {
                EXPECT_TRUE(is_finite(smp->f) && std::isfinite(smp->pdf) && is_finite(smp->wi));
            }
        }
}

}  // namespace
}  // namespace purl::test
