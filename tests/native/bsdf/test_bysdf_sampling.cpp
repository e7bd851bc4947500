// BYSDF sampling: chi-square of sample against pdf over random configurations and incident
// directions (grazing and back-facing included), and sample records consistent with eval/pdf.
#include <gtest/gtest.h>

#include "support/chi_square.h"
#include "random_bysdf.h"

namespace purl::test {
namespace {

// Incident cosines: a spread over (0, 1] plus grazing ones; negative = viewer below the frame.
float incident_cos(Rng& rng, int k) {
    static const float fixed[] = {0.002f, 0.01f, 0.05f, -0.3f, 1.0f, -0.005f};
    if (k < 6) return fixed[k];
    const float c = std::max(0.003f, rng.next_float());
    return k % 5 == 0 ? -c : c;
}

TEST(BysdfSampling, ChiSquareOverRandomConfigurations) {
    constexpr int kRuns = 60;
    Rng rng(2024);
    int failures = 0;
    for (int k = 0; k < kRuns; ++k) {
        const BysdfParams p = random_bysdf_params(rng);
        const Bysdf m(p, random_shading_point(rng));
        const Vec3 wo = direction_with_cos(rng, incident_cos(rng, k));
        Chi2Options o;
        o.test_count = kRuns;
        o.seed = 1000 + k;
        o.samples = 200000;
        int record_mismatches = 0;
        const Chi2Result r = chi2_test(
            [&](Vec3 u) -> std::optional<Vec3> {
                const auto s = m.sample(wo, u.x, {u.y, u.z});
                if (!s) return std::nullopt;
                // The record must be what eval and pdf say at the sampled direction.
                const BsdfEvalPdf ep = m.eval_pdf(wo, s->wi);
                const bool same_side = (s->wi.z > 0) == (wo.z > 0);
                if (std::fabs(ep.pdf - s->pdf) > 1e-5f * s->pdf ||
                    std::fabs(average(ep.f) - average(s->f)) > 1e-5f * average(s->f) + 1e-9f ||
                    same_side != ((s->flags & kBsdfReflection) != 0))
                    ++record_mismatches;
                return s->wi;
            },
            [&](Vec3 wi) { return double(m.pdf(wo, wi)); }, o);
        EXPECT_EQ(record_mismatches, 0) << "run " << k;
        if (!r.passed) ++failures;
        EXPECT_TRUE(r.passed) << "run " << k << " eta " << p.eta << " alpha (" << p.specular_roughness_along << ", "
                              << p.specular_roughness_across << ", " << p.transmission_roughness << ") B "
                              << p.body_share << " wo " << wo.x << " " << wo.y << " " << wo.z << "\n" << r.message;
    }
    std::printf("BYSDF chi-square: %d of %d configurations rejected at Sidak-corrected 1%%\n", failures, kRuns);
}

TEST(BysdfSampling, ImportanceEstimateMatchesQuadrature) {
    // The sampled estimate of the albedo, mean of f cos / pdf, against a quadrature of f cos
    // that never calls sample or pdf: a pdf that disagrees with sample biases the former.
    Rng rng(77);
    for (int k = 0; k < 6; ++k) {
        const Bysdf m(random_bysdf_params(rng), random_shading_point(rng));
        const Vec3 wo = direction_with_cos(rng, k == 0 ? 0.02f : 0.1f + 0.9f * rng.next_float());
        const double exact =
            integrate_sphere([&](Vec3 wi) { return double(average(m.eval(wo, wi))) * std::fabs(wi.z); }, 20, 40, 1e-7);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        Rng u(500 + k);
        for (int i = 0; i < n; ++i) {
            const auto s = m.sample(wo, u.next_float(), {u.next_float(), u.next_float()});
            const double w = s ? double(average(s->weight())) : 0.0;
            sum += w;
            sum2 += w * w;
        }
        const double mean = sum / n, stderr_ = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, exact, 4 * stderr_ + 1e-4) << "run " << k << " wo.z " << wo.z;
    }
}

TEST(BysdfSampling, ReflectionAndTransmissionGoWhereTheFlagsSay) {
    Rng rng(5);
    const Bysdf m(random_bysdf_params(rng), random_shading_point(rng));
    int seen[4] = {0, 0, 0, 0};
    for (int i = 0; i < 20000; ++i) {
        const Vec3 wo = direction_with_cos(rng, rng.next_float() * 2 - 1);
        const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        if (!s) continue;
        ++seen[s->lobe];
        EXPECT_EQ(s->wi.z * wo.z > 0, (s->flags & kBsdfReflection) != 0);
        EXPECT_EQ((s->flags & kBsdfBody) != 0, s->lobe >= Bysdf::kBodyReflection);
        EXPECT_NEAR(length(s->wi), 1.0f, 1e-5f);
    }
    for (int lobe = 0; lobe < 4; ++lobe) EXPECT_GT(seen[lobe], 20) << "lobe " << lobe;
}

}  // namespace
}  // namespace purl::test
