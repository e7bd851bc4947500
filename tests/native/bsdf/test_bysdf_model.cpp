// BYSDF parameters and lobe values against closed forms, conventions (tangent = +x,
// two-sided), shadowing, ply colours and extinction.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "bsdf/fresnel.h"
#include "bsdf/lommel_seeliger.h"
#include "random_bysdf.h"
#include "base/input_error.h"

namespace purl::test {
namespace {

const Vec3 kUp(0, 0, 1), kDown(0, 0, -1);

TEST(BysdfParams, TableDescribesEveryFieldOnce) {
    std::set<std::string> names;
    size_t covered = 0;
    for (const ParamInfo& i : bysdf_param_table()) {
        EXPECT_TRUE(names.insert(i.name).second) << "duplicate " << i.name;
        EXPECT_LE(i.offset + i.components * sizeof(float), sizeof(BysdfParams)) << i.name;
        EXPECT_GT(std::string(i.doc).size(), 10u) << i.name;
        for (int c = 0; c < i.components; ++c) {
            EXPECT_GE(i.default_value[c], i.min_value) << i.name;
            EXPECT_LE(i.default_value[c], i.max_value) << i.name;
        }
        covered += i.components * sizeof(float);
    }
    EXPECT_EQ(covered, sizeof(BysdfParams));  // no field without a declaration
    EXPECT_EQ(names.count("ply_color_12"), 1u);
}

TEST(BysdfParams, DefaultsFollowThePrototype) {
    const BysdfParams p = default_bysdf_params();
    EXPECT_FLOAT_EQ(p.eta, 1.5f);
    EXPECT_FLOAT_EQ(p.specular_roughness_along, 0.2f);
    EXPECT_FLOAT_EQ(p.specular_roughness_across, 0.3f);
    EXPECT_FLOAT_EQ(p.transmission_roughness, 0.9f);
    EXPECT_FLOAT_EQ(p.body_transmission_albedo.x, 6 * p.body_reflection_albedo.x);
    EXPECT_FLOAT_EQ(p.sigma_t_specular, 5.5f * 2.0f);  // 5.5 per unit at yarn radius 2
    EXPECT_FLOAT_EQ(p.ply_colors[11].y, 1.0f);
    EXPECT_NO_THROW(check_bysdf_params(p, "scene.json", "yarns[0].material"));
}

TEST(BysdfParams, CheckNamesTheFieldAndReason) {
    BysdfParams p = default_bysdf_params();
    p.eta = 0.5f;
    try {
        check_bysdf_params(p, "scene.json", "yarns[0].material");
        FAIL() << "eta 0.5 accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "scene.json");
        EXPECT_EQ(e.place(), "yarns[0].material.eta");
    }
    p = default_bysdf_params();
    p.ply_colors[3].y = std::nanf("");
    EXPECT_THROW(check_bysdf_params(p, "f", "m"), InputError);
    p = default_bysdf_params();
    p.ply_color_count = 2.5f;
    EXPECT_THROW(check_bysdf_params(p, "f", "m"), InputError);
}

BysdfParams white() { return white_bysdf_params(1.0f); }

TEST(BysdfLobes, BodyLobesMatchClosedForms) {
    BysdfParams p = white();
    p.lommel_seeliger_weight = 0.0f;
    p.body_reflection_share = 1.0f;
    const Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.8f)), wi = normalize(Vec3(-0.5f, 0.1f, 0.4f));
    EXPECT_NEAR(Bysdf(p, {}).eval(wo, wi).x, kInvPi, 1e-6f);  // pure Lambert
    EXPECT_NEAR(Bysdf(p, {}).eval(wo, -wi).x, 0.0f, 1e-7f);
    p.body_reflection_share = 0.0f;
    EXPECT_NEAR(Bysdf(p, {}).eval(wo, -wi).x, kInvPi, 1e-6f);
    EXPECT_NEAR(Bysdf(p, {}).eval(wo, wi).x, 0.0f, 1e-7f);
    // LS at normal incidence and exitance: (1/(8 pi) + 1/pi) / (1 + A_LS(1)).
    p.body_reflection_share = 1.0f;
    p.lommel_seeliger_weight = 1.0f;
    const float expected = (1 / (8 * kPi) + kInvPi) / (1 + lommel_seeliger_albedo(1.0f));
    EXPECT_NEAR(Bysdf(p, {}).eval(kUp, kUp).x, expected, 1e-6f);
}

TEST(BysdfLobes, SpecularLobesMatchClosedFormsAtNormalIncidence) {
    BysdfParams p = white_bysdf_params(0.0f);
    p.specular_roughness_along = p.specular_roughness_across = 0.3f;
    p.transmission_roughness = 0.6f;
    p.eta = 1.5f;
    const Bysdf m(p, {});
    const float f0 = fresnel_dielectric(1.0f, 1.5f);
    // Mirror configuration: h = n, D = 1/(pi alpha^2), G = 1.
    EXPECT_NEAR(m.eval(kUp, kUp).x, f0 / (kPi * 0.09f * 4), 1e-4f);
    // Straight through: h = n, Jacobian eta^2 / (eta - 1)^2.
    EXPECT_NEAR(m.eval(kUp, kDown).x, (1 - f0) * 2.25f / (0.25f * kPi * 0.36f), 1e-3f);
}

TEST(BysdfLobes, TangentIsPlusX) {
    // Smooth along the fiber, rough across it: the highlight is narrow in x, wide in y.
    BysdfParams p = white_bysdf_params(0.0f);
    p.specular_roughness_along = 0.05f;
    p.specular_roughness_across = 0.5f;
    const Bysdf m(p, {});
    const Vec3 wo = kUp;
    const float tilt = 0.15f;
    const float off_x = m.eval(wo, normalize(Vec3(tilt, 0, 1))).x, off_y = m.eval(wo, normalize(Vec3(0, tilt, 1))).x;
    EXPECT_LT(off_x * 5, off_y);
}

TEST(BysdfLobes, TwoSidedByMirroring) {
    Rng rng(4);
    const Bysdf m(random_bysdf_params(rng), random_shading_point(rng));
    for (int i = 0; i < 200; ++i) {
        const Vec3 wo = direction_with_cos(rng, rng.next_float()), wi = direction_with_cos(rng, 2 * rng.next_float() - 1);
        const Vec3 wo_m(wo.x, wo.y, -wo.z), wi_m(wi.x, wi.y, -wi.z);
        EXPECT_EQ(m.eval(wo, wi, {0.5f}).y, m.eval(wo_m, wi_m, {0.5f}).y);
        EXPECT_EQ(m.pdf(wo, wi), m.pdf(wo_m, wi_m));
        const auto a = m.sample(wo, 0.3f, {0.2f, 0.7f}), b = m.sample(wo_m, 0.3f, {0.2f, 0.7f});
        ASSERT_EQ(a.has_value(), b.has_value());
        if (a) {
            EXPECT_EQ(a->wi.z, -b->wi.z);
        }
    }
}

TEST(BysdfLobes, ShadowingDimsOnlyTheBodyWithFloors) {
    BysdfParams p = white_bysdf_params(0.5f);
    p.ply_shadow_floor = 0.6f;
    p.fiber_shadow_floor = 0.5f;
    p.ply_crossing = 0;  // G_p from the map (traced: from the plies crossed)
    BysdfParams spec_only = p, body_only = p;
    spec_only.body_reflection_albedo = spec_only.body_transmission_albedo = Vec3(0.0f);
    body_only.specular_reflection_albedo = body_only.specular_transmission_albedo = Vec3(0.0f);
    const Vec3 wo = normalize(Vec3(0.2f, 0.1f, 0.9f)), wi = normalize(Vec3(-0.3f, 0.4f, 0.7f));
    BysdfShadingPoint lit, dark, half;
    dark.ply_shadow = dark.fiber_shadow = 0.0f;   // clamped to the floors
    half.ply_shadow = 0.8f;
    half.fiber_shadow = 0.7f;
    const float body_lit = Bysdf(body_only, lit).eval(wo, wi).x;
    EXPECT_NEAR(Bysdf(body_only, dark).eval(wo, wi).x, body_lit * 0.6f * 0.5f, 1e-6f);
    EXPECT_NEAR(Bysdf(body_only, half).eval(wo, wi).x, body_lit * 0.8f * 0.7f, 1e-6f);
    EXPECT_EQ(Bysdf(spec_only, dark).eval(wo, wi).x, Bysdf(spec_only, lit).eval(wo, wi).x);
}

TEST(BysdfLobes, PlyAndYarnColoursMultiplyTheBodyAlbedo) {
    BysdfParams p = white_bysdf_params(1.0f);
    p.body_reflection_albedo = Vec3(0.5f);
    p.ply_color_count = 3;
    p.ply_colors[0] = Vec3(1, 0, 0);
    p.ply_colors[1] = Vec3(0, 1, 0);
    p.ply_colors[2] = Vec3(0.2f, 0.4f, 0.6f);
    p.ply_colors[3] = Vec3(0, 0, 1);  // beyond the count: never used
    const Vec3 wo = kUp, wi = normalize(Vec3(0.3f, 0.3f, 0.9f));
    BysdfShadingPoint sp;
    sp.ply_index = 5;  // 5 mod 3 = 2
    sp.yarn_color = Vec3(1.0f, 0.5f, 1.0f);
    const Vec3 f = Bysdf(p, sp).eval(wo, wi);
    BysdfParams plain = p;
    plain.ply_color_count = 1;
    plain.ply_colors[0] = Vec3(1.0f);
    const Vec3 g = Bysdf(plain, {}).eval(wo, wi);
    EXPECT_NEAR(f.x / g.x, 0.2f * 1.0f, 1e-5f);
    EXPECT_NEAR(f.y / g.y, 0.4f * 0.5f, 1e-5f);
    EXPECT_NEAR(f.z / g.z, 0.6f * 1.0f, 1e-5f);
}

TEST(BysdfLobes, NothingToScatterMeansNoSample) {
    BysdfParams p = white_bysdf_params(0.5f);
    p.specular_reflection_albedo = p.specular_transmission_albedo = Vec3(0.0f);
    p.body_reflection_albedo = p.body_transmission_albedo = Vec3(0.0f);
    const Bysdf m(p, {});
    EXPECT_FALSE(m.sample(kUp, 0.5f, {0.5f, 0.5f}).has_value());
    EXPECT_EQ(m.pdf(kUp, kDown), 0.0f);
    EXPECT_TRUE(is_black(m.eval(kUp, normalize(Vec3(1, 0, 1)))));
}

TEST(BysdfLobes, LobeProbabilitiesFollowEnergy) {
    BysdfParams p = white_bysdf_params(0.25f);
    p.body_reflection_share = 0.8f;
    const Bysdf m(p, {});
    float prob[4];
    m.lobe_probabilities(kUp, prob);
    const float f0 = fresnel_dielectric(1.0f, 1.5f);
    EXPECT_NEAR(prob[Bysdf::kSpecularReflection], 0.75f * f0, 1e-6f);
    EXPECT_NEAR(prob[Bysdf::kSpecularTransmission], 0.75f * (1 - f0), 1e-6f);
    EXPECT_NEAR(prob[Bysdf::kBodyReflection], 0.25f * 0.8f, 1e-6f);
    EXPECT_NEAR(prob[Bysdf::kBodyTransmission], 0.25f * 0.2f, 1e-6f);
}

}  // namespace
}  // namespace purl::test
