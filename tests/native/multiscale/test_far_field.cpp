// The tabulated far field (render/far_field.h) against the sampled far field it is built
// from (MultiscaleBysdf in mode Far, averaged over the offset h0, the position along the yarn
// and the view azimuth), its sampling against its pdf (shared chi-square harness), and the
// colours it leaves out and multiplies back at lookup.
#include <gtest/gtest.h>

#include <cstdio>

#include "support/chi_square.h"
#include "math/rng.h"
#include "multiscale_fixture.h"
#include "render/far_field.h"

namespace purl::test {
namespace {

// Two ply colours and a coloured body: the table's colour classes and the linearity in colour.
StraightYarn coloured_yarn() {
    StraightYarn s;
    s.params.ply_color_count = 2;
    s.params.ply_colors[0] = Vec3(1.0f, 0.6f, 0.3f);
    s.params.ply_colors[1] = Vec3(0.3f, 0.7f, 1.0f);
    s.params.body_reflection_albedo = Vec3(0.2f, 0.5f, 0.9f);
    s.params.specular_reflection_albedo = Vec3(0.9f, 0.8f, 0.7f);
    return s;
}

// The far frame of the renderer for a view direction wo (world) on the fixture's yarn (+z).
Frame far_frame(Vec3 wo) {
    const Vec3 axis(0, 0, 1);
    return Frame::from_normal_tangent(normalize(wo - axis * dot(wo, axis)), axis);
}

// Integrals of f |cos| against broad lobes max(0, wi.l)^4 around six light directions,
// by the same uniform directions for both models.
struct LobeIntegrals {
    Vec3 value[6];
};

const Vec3 kLights[6] = {{1, 0, 0.2f}, {-1, 0, 0.1f}, {0, 1, 0}, {0.6f, 0.6f, 0.5f}, {0.2f, -0.9f, -0.6f},
                         {-0.5f, 0.3f, 0.8f}};

template <class Integrand>
LobeIntegrals integrate_lobes(Integrand&& f, int directions, uint64_t seed) {
    LobeIntegrals out;
    Rng rng(seed);
    for (int i = 0; i < directions; ++i) {
        const float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
        const float r = safe_sqrt(1 - z * z);
        const Vec3 wi(r * std::cos(phi), r * std::sin(phi), z);
        const Vec3 v = f(wi) * (4 * kPi / directions);
        for (int l = 0; l < 6; ++l) {
            const float w = std::max(0.0f, dot(wi, normalize(kLights[l])));
            out.value[l] += v * (w * w * w * w);
        }
    }
    return out;
}

// Worst difference, over the view angles, lobes and channels, between the table and the
// sampled far field, relative to the largest lobe integral of that view.
double worst_difference(const StraightYarn& s, const FarFieldTable& table) {
    const FarFieldBsdf far(table, s.params);
    // View angles from the normal plane: on and between the table's nodes, and grazing.
    const float views[] = {0.0f, 0.33f, 0.8f, 1.2f};
    double worst = 0;
    for (float psi : views) {
        const Vec3 wo = -StraightYarn::direction(psi);
        const Frame frame = far_frame(wo);
        const Vec3 wo_l = frame.to_local(wo);
        const float table_hit = 1 - far.pass_fraction(wo_l);
        const LobeIntegrals tabulated = integrate_lobes(
            [&](Vec3 wi) {
                const Vec3 wi_l = frame.to_local(wi);
                return far.eval(wo_l, wi_l) * (std::fabs(wi_l.z) * table_hit);
            },
            2000, 11);
        // The sampled far field: the mean over h0, the position along the yarn and the jitter
        // (the view azimuth is fixed: the fixture's rays come from +x).
        Rng rng(99);
        const int queries = 600;
        double pass = 0;
        std::vector<MultiscaleBysdf> models;
        models.reserve(queries);
        for (int q = 0; q < queries; ++q) {
            const float y = -0.999f + 1.998f * (q + rng.next_float()) / queries;
            models.emplace_back(s.yarn(), s.settings,
                                s.query(y, psi, 30 + 20 * rng.next_float(), 0.0f, MultiscaleMode::Far, rng.next_float()));
            pass += models.back().empty() ? 1.0 : models.back().pass_fraction();
        }
        const LobeIntegrals sampled = integrate_lobes(
            [&](Vec3 wi) {
                Vec3 sum(0.0f);
                for (const MultiscaleBysdf& m : models) sum += model_integrand(m, wo, wi);
                return sum / float(queries);
            },
            2000, 11);
        double largest = 0;
        for (const Vec3& v : sampled.value) largest = std::max({largest, double(v.x), double(v.y), double(v.z)});
        double view_worst = 0;
        for (int l = 0; l < 6; ++l)
            for (int c = 0; c < 3; ++c)
                view_worst = std::max(view_worst, std::fabs(double(tabulated.value[l][c] - sampled.value[l][c])) / largest);
        // And in the sum of all lobe integrals: a bias shared by every lobe (measured 0.99-1.01,
        // 1.05 grazing).
        double sum_tabulated = 0, sum_sampled = 0;
        for (int l = 0; l < 6; ++l)
            for (int c = 0; c < 3; ++c) {
                sum_tabulated += tabulated.value[l][c];
                sum_sampled += sampled.value[l][c];
            }
        const double ratio = sum_tabulated / sum_sampled;
        std::printf("psi %.2f: pass fraction table %.3f sampled %.3f; lobe integrals worst difference %.3f of the largest, "
                    "sum ratio %.4f\n", psi, 1 - table_hit, pass / queries, view_worst, ratio);
        EXPECT_NEAR(ratio, 1.0, psi < 1 ? 0.03 : 0.08) << psi;
        EXPECT_NEAR(1 - table_hit, pass / queries, 0.03) << psi;
        worst = std::max(worst, view_worst);
    }
    return worst;
}

TEST(FarField, TableMatchesTheSampledFarField) {
    // The traced ply crossing (default): the table's lobe markers with the other plies' A_k
    // from the material's colours, per channel. (Leaving the plies crossed out of the table, as
    // before issue 26's far-field work: worst 0.33-0.43, sum ratio 1.20-1.26.)
    const StraightYarn s = coloured_yarn();
    const auto table = far_field_table(s.description, s.params, s.settings);
    std::printf("table: %d classes, %zu bytes, built in %.2f s\n", table->classes(), table->memory_bytes(),
                table->build_seconds());
    const double worst = worst_difference(s, *table);
    // Measured 0.04-0.07 (0.03-0.06 with a 4x larger table build): the noise of the two
    // estimates plus the table's averaging over curve keys. A wrong cosine or colour is 20 %+.
    std::printf("worst %.3f\n", worst);
    EXPECT_LT(worst, 0.10);
}

TEST(FarField, ColoursMultiplyAtLookup) {
    // The lobe at the hit is linear in its colours, which enter at lookup (a curve's own body
    // colour, with_body_color, and the ply colours); the plies crossed on the way out pass on
    // a product of the material's albedos, so another material colour is another table.
    const StraightYarn s = coloured_yarn();
    BysdfParams other = with_body_color(s.params, Vec3(0.9f, 0.2f, 0.1f));
    other.specular_transmission_albedo = Vec3(0.1f, 0.9f, 0.5f);
    EXPECT_NE(far_field_table(s.description, s.params, s.settings).get(),
              far_field_table(s.description, other, s.settings).get());
    BysdfParams rougher = s.params;
    rougher.specular_roughness_along += 0.1f;
    EXPECT_NE(far_field_table(s.description, s.params, s.settings).get(),
              far_field_table(s.description, rougher, s.settings).get());

    const auto table = far_field_table(s.description, s.params, s.settings);
    const Vec3 wo = normalize(Vec3(0.3f, 0.0f, 0.9f));
    Rng rng(5);
    for (int i = 0; i < 200; ++i) {
        const float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
        const Vec3 wi(safe_sqrt(1 - z * z) * std::cos(phi), safe_sqrt(1 - z * z) * std::sin(phi), z);
        // White material minus its parts = the parts, lobe group by lobe group.
        const FarFieldBsdf a(*table, s.params), b(*table, other);
        const Vec3 fa = a.eval(wo, wi), fb = b.eval(wo, wi);
        BysdfParams sum = s.params;
        sum.body_reflection_albedo = Vec3(0.2f, 0.5f, 0.9f) * 0.5f;
        sum.body_transmission_albedo = s.params.body_transmission_albedo * 0.5f;
        const Vec3 half_body = FarFieldBsdf(*table, sum).eval(wo, wi);
        BysdfParams no_body = s.params;
        no_body.body_reflection_albedo = no_body.body_transmission_albedo = Vec3(0.0f);
        const Vec3 spec = FarFieldBsdf(*table, no_body).eval(wo, wi);
        // f = spec + body; halving the body albedos halves the body part.
        const Vec3 expected = spec + (fa - spec) * 0.5f;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(half_body[c], expected[c], 1e-5f * (1 + fa[c])) << i;
        EXPECT_TRUE(is_finite(fb));
    }
}

TEST(FarField, ChiSquare) {
    const StraightYarn s = coloured_yarn();
    const auto table = far_field_table(s.description, s.params, s.settings);
    const FarFieldBsdf far(*table, s.params);
    // wo: side view, between two nodes (interpolated), steep, and with an azimuth (wo.y != 0).
    const Vec3 cases[] = {{0.0f, 0.0f, 1.0f}, {0.41f, 0.0f, 0.8f}, {-0.9f, 0.0f, 0.3f}, {0.2f, 0.7f, 0.4f}};
    int failures = 0;
    for (size_t k = 0; k < std::size(cases); ++k) {
        const Vec3 wo = normalize(cases[k]);
        Chi2Options o;
        o.samples = 150000;
        o.test_count = static_cast<int>(std::size(cases));
        o.seed = 900 + k;
        int mismatches = 0;
        const Chi2Result r = chi2_model(far, wo, o, mismatches);
        EXPECT_EQ(mismatches, 0) << k;
        EXPECT_TRUE(r.passed) << k << "\n" << r.message;
        if (!r.passed) ++failures;
        std::printf("far table wo %zu: chi2 %.1f dof %d p %.3f pdf mass %.4f\n", k, r.statistic, r.dof, r.p_value,
                    r.pdf_integral);
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << k;
    }
    EXPECT_EQ(failures, 0);
}

}  // namespace
}  // namespace purl::test
