// White furnace: with albedos 1, no extinction and no shadowing, the body lobes return all
// the energy they are given, and the whole BYSDF never returns more than it receives.
#include <gtest/gtest.h>

#include <cstdio>

#include "support/chi_square.h"
#include "random_bysdf.h"

namespace purl::test {
namespace {

// Directional albedo by quadrature of f |cos| over the sphere (no sampling involved).
double albedo_quadrature(const Bysdf& m, Vec3 wo, double tolerance = 1e-6) {
    return integrate_sphere([&](Vec3 wi) { return double(average(m.eval(wo, wi))) * std::fabs(wi.z); }, 20, 40,
                            tolerance);
}

struct Estimate {
    double mean, standard_error;
};
// Directional albedo by importance sampling: mean of f |cos| / pdf.
Estimate albedo_sampled(const Bysdf& m, Vec3 wo, int n, uint64_t seed) {
    Rng u(seed);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const auto s = m.sample(wo, u.next_float(), {u.next_float(), u.next_float()});
        const double w = s ? double(average(s->weight())) : 0.0;
        sum += w;
        sum2 += w * w;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

const float kAnglesDeg[] = {0, 15, 30, 45, 60, 75, 85, 89, 89.9f};

Vec3 incident(float degrees) {
    const float t = degrees * kPi / 180;
    return {std::sin(t), 0.0f, std::cos(t)};
}

TEST(BysdfFurnace, BodyLobesConserveEnergy) {
    std::printf("body lobes (B = 1), albedo by quadrature\n theta_o |  r=0.5,w=1  r=1,w=1  r=0.3,w=0.5  r0=0.2,t=1\n");
    for (float deg : kAnglesDeg) {
        std::printf("  %5.1f  |", deg);
        for (int variant = 0; variant < 4; ++variant) {
            BysdfParams p = white_bysdf_params(1.0f);
            const float r[] = {0.5f, 1.0f, 0.3f, 0.2f}, w[] = {1.0f, 1.0f, 0.5f, 1.0f};
            p.body_reflection_share = r[variant];
            p.lommel_seeliger_weight = w[variant];
            p.body_reflection_fresnel = variant == 3 ? 1.0f : 0.0f;
            const Bysdf m(p, BysdfShadingPoint{});
            const double a = albedo_quadrature(m, incident(deg));
            std::printf("  %9.5f", a);
            EXPECT_NEAR(a, 1.0, 0.01) << "theta_o " << deg << " variant " << variant;
        }
        std::printf("\n");
    }
}

TEST(BysdfFurnace, BodyAlbedoFollowsTheAlbedoColour) {
    // Not trivially 1: a grey albedo and B must scale the returned energy linearly.
    BysdfParams p = white_bysdf_params(0.8f);
    p.specular_reflection_albedo = p.specular_transmission_albedo = Vec3(0.0f);
    p.body_reflection_albedo = Vec3(0.5f);
    p.body_transmission_albedo = Vec3(0.25f);
    p.body_reflection_share = 0.6f;
    const Bysdf m(p, BysdfShadingPoint{});
    const double expected = 0.8 * (0.6 * 0.5 + 0.4 * 0.25);
    for (float deg : {0.0f, 60.0f, 89.0f}) EXPECT_NEAR(albedo_quadrature(m, incident(deg)), expected, 1e-3 * expected);
}

TEST(BysdfFurnace, WholeModelNeverReturnsMoreThanItReceives) {
    struct Case {
        const char* name;
        float along, across, transmission, eta;
    };
    const Case cases[] = {{"default alphas (0.2,0.3 | 0.9), eta 1.5", 0.2f, 0.3f, 0.9f, 1.5f},
                          {"smooth (0.05,0.05 | 0.1), eta 1.5", 0.05f, 0.05f, 0.1f, 1.5f},
                          {"rough (1,1 | 1), eta 1.33", 1.0f, 1.0f, 1.0f, 1.33f},
                          {"mixed (0.02,0.6 | 0.5), eta 2.5", 0.02f, 0.6f, 0.5f, 2.5f}};
    const int n = 100000;
    for (const Case& c : cases) {
        std::printf("%s: albedo by importance sampling (+- 1 standard error)\n"
                    " theta_o |  specular only (B=0)   |  B=0.5 total\n", c.name);
        for (float deg : kAnglesDeg) {
            double values[2];
            for (int k = 0; k < 2; ++k) {
                BysdfParams p = white_bysdf_params(k == 0 ? 0.0f : 0.5f);
                p.specular_roughness_along = c.along;
                p.specular_roughness_across = c.across;
                p.transmission_roughness = c.transmission;
                p.eta = c.eta;
                const Bysdf m(p, BysdfShadingPoint{});
                const Estimate e = albedo_sampled(m, incident(deg), n, 31 + k);
                values[k] = e.mean;
                std::printf(k == 0 ? "  %5.1f  |  %.4f +- %.4f     |" : "  %.4f +- %.4f\n", k == 0 ? deg : e.mean,
                            k == 0 ? e.mean : e.standard_error, e.standard_error);
                EXPECT_LE(e.mean, 1.0 + 4 * e.standard_error + 1e-3) << c.name << " theta_o " << deg;
            }
            // The body half is exactly 0.5, so the total is 0.5 + half the specular albedo.
            EXPECT_NEAR(values[1], 0.5 + 0.5 * values[0], 0.02) << c.name << " theta_o " << deg;
        }
    }
}

TEST(BysdfFurnace, SampledAndQuadratureAlbedosAgree) {
    // Both estimators on the default white model, so neither one alone is trusted.
    const Bysdf m(white_bysdf_params(0.5f), BysdfShadingPoint{});
    for (float deg : {0.0f, 45.0f, 80.0f}) {
        const Estimate e = albedo_sampled(m, incident(deg), 200000, 3);
        EXPECT_NEAR(e.mean, albedo_quadrature(m, incident(deg), 1e-7), 4 * e.standard_error + 1e-3) << deg;
    }
}

TEST(BysdfFurnace, ExtinctionOnlyDimsTransmission) {
    BysdfParams p = white_bysdf_params(0.5f);
    p.sigma_t_specular = 3.0f;
    p.sigma_t_body = 0.5f;
    p.ply_crossing = 0;  // the paper's tau^N_i
    BysdfShadingPoint sp;
    sp.plies_crossed = 2;
    const Bysdf m(p, sp);
    const Vec3 wo = incident(30), reflected(-0.3f, 0.2f, 0.93f), transmitted(-0.2f, 0.1f, -0.97f);
    EXPECT_EQ(average(m.eval(wo, reflected, {0.0f})), average(m.eval(wo, reflected, {1.7f})));
    // tau^N_i: the body transmission drops by exp(-0.5 * 1.2)^2.
    BysdfParams body_only = p;
    body_only.specular_transmission_albedo = Vec3(0.0f);
    const Bysdf b(body_only, sp);
    EXPECT_NEAR(average(b.eval(wo, transmitted, {1.2f})) / average(b.eval(wo, transmitted, {0.0f})),
                std::exp(-2 * 0.5 * 1.2), 1e-5);
    EXPECT_NEAR(m.transmittance(0, 0.4f), std::exp(-2 * 3.0 * 0.4), 1e-6);
}

// Traced ply crossing: the hit ply's own path attenuates the transmission, N_i does not count,
// and each other ply crossed passes on A_k (its transmission and reflection) on every lobe.
TEST(BysdfFurnace, TracedCrossingAttenuatesByThePliesCrossed) {
    BysdfParams p = default_bysdf_params();
    p.ply_crossing = 1;
    p.sigma_t_specular = 3.0f;
    p.sigma_t_body = 0.5f;
    BysdfShadingPoint sp;
    sp.plies_crossed = 4;  // ignored
    sp.ply_shadow = 0.1f;  // ignored: the plies crossed are the ply shadowing
    sp.fiber_shadow = 0.9f;
    sp.mean_fiber_shadow = 0.8f;
    const Bysdf m(p, sp);
    EXPECT_NEAR(m.transmittance(1, 0.4f), std::exp(-0.5 * 0.4), 1e-6);
    const Vec3 wo = incident(30), reflected(-0.3f, 0.2f, 0.93f), transmitted(-0.2f, 0.1f, -0.97f);
    BysdfParams paper = p;
    paper.ply_crossing = 0;
    paper.ply_shadow_floor = 1.0f;
    BysdfShadingPoint one = sp;
    one.plies_crossed = 1;
    const Bysdf unshadowed(paper, one);  // G_p 1 and N_i 1: what traced gives with no other ply
    PlyCrossings alone;
    alone.own = 0.7f;
    for (Vec3 wi : {reflected, transmitted}) {
        const Vec3 a = m.eval(wo, wi, {1.3f, &alone}), b = unshadowed.eval(wo, wi, {0.7f});
        EXPECT_NEAR(a.x, b.x, 1e-6f * std::max(1.0f, b.x));
    }
    // Two more plies: every lobe times A_1 A_2, each A_k < 1.
    PlyCrossings two = alone;
    two.others = 2;
    two.other[0] = 0.3f;
    two.other[1] = 0.5f;
    const Vec3 a1 = m.other_plies_transmission({0, 1, {0.3f}}), a2 = m.other_plies_transmission({0, 1, {0.5f}});
    for (int c = 0; c < 3; ++c) {
        EXPECT_LT((&a1.x)[c], 1.0f);
        EXPECT_LT((&a2.x)[c], (&a1.x)[c] + 1e-7f);  // the longer path passes less
    }
    for (Vec3 wi : {reflected, transmitted}) {
        const Vec3 f2 = m.eval(wo, wi, {1.3f, &two}), f0 = m.eval(wo, wi, {1.3f, &alone});
        EXPECT_NEAR(f2.x, f0.x * a1.x * a2.x, 1e-6f * std::max(1.0f, f0.x));
    }
    // A white ply without extinction passes everything on; the paper ignores PlyCrossings.
    const Bysdf white(white_bysdf_params(0.5f), sp);
    EXPECT_NEAR(average(white.other_plies_transmission(two)), 1.0f, 1e-5f);
    EXPECT_EQ(average(unshadowed.eval(wo, reflected, {0.0f, &two})), average(unshadowed.eval(wo, reflected)));
}

// Spread crossing: light that met no other ply sees the traced lobes; light another ply scattered
// arrives diffuse (the lobes' albedo on wi's side over pi), times what the other plies pass on,
// averaged over the ray (their transmission) and its spread directions (their whole A_k).
TEST(BysdfFurnace, SpreadCrossingMakesScatteredLightDiffuse) {
    BysdfParams p = default_bysdf_params();
    p.ply_crossing = 1;
    p.sigma_t_specular = 3.0f;
    p.sigma_t_body = 0.5f;
    BysdfParams q = p;
    q.ply_crossing = 2;
    BysdfShadingPoint sp;
    sp.fiber_shadow = 0.9f;
    sp.mean_fiber_shadow = 0.8f;
    const Bysdf traced(p, sp), spread(q, sp);
    const Vec3 wo = incident(30), reflected(-0.3f, 0.2f, 0.93f), reflected2(0.5f, -0.1f, 0.86f),
               transmitted(-0.2f, 0.1f, -0.97f), transmitted2(0.4f, 0.3f, -0.87f);
    PlyCrossings alone;
    alone.own = 0.4f;
    alone.spread_done = true;
    for (Vec3 wi : {reflected, transmitted})
        EXPECT_EQ(average(spread.eval(wo, wi, {1.0f, &alone})),
                  average(traced.eval(wo, wi, {1.0f, &alone})));
    // One other ply on the ray and on one of the four spread directions.
    PlyCrossings crossed = alone;
    crossed.others = 1;
    crossed.other[0] = 0.3f;
    crossed.spread_others[2] = 1;
    crossed.spread[2][0] = 0.5f;
    // On the ray the crossed ply passes on its transmission only (its reflection leaves toward
    // the light); beside it, its whole A_k.
    const PlyPassOn& pass = spread.pass_on();
    const Vec3 a_ray = pass.specular_transmission * std::exp(-3.0f * 0.3f) +
                       pass.body_transmission * std::exp(-0.5f * 0.3f);
    EXPECT_LT(a_ray.x, spread.other_plies_transmission({0, 1, {0.3f}}).x);
    const Vec3 a_side = spread.other_plies_transmission({0, 1, {0.5f}});
    const Vec3 scattered = (a_ray + a_side) * (1.0f / (1 + kSpreadDirections));
    Vec3 albedo[4];
    spread.lobe_albedos(normalize(wo), albedo);
    const Vec3 refl = spread.eval(wo, reflected, {1.0f, &crossed});
    const Vec3 trans = spread.eval(wo, transmitted, {1.0f, &crossed});
    EXPECT_NEAR(refl.x * kPi, (albedo[0].x + albedo[2].x) * scattered.x, 1e-5f);
    const float own_spec = std::exp(-3.0f * 0.4f), own_body = std::exp(-0.5f * 0.4f);
    EXPECT_NEAR(trans.x * kPi, (albedo[1].x * own_spec + albedo[3].x * own_body) * scattered.x, 1e-5f);
    // Diffuse: the same value toward any wi on the same side.
    EXPECT_NEAR(refl.x, spread.eval(wo, reflected2, {1.0f, &crossed}).x, 1e-6f);
    EXPECT_NEAR(trans.x, spread.eval(wo, transmitted2, {1.0f, &crossed}).x, 1e-6f);
}

}  // namespace
}  // namespace purl::test
