// Mode selection, h sample counts, settings, pass-through and the aggregate variant.
#include <gtest/gtest.h>

#include <string>

#include "multiscale_fixture.h"
#include "base/input_error.h"

namespace purl::test {
namespace {

AzimuthalFootprint footprint(float h0, float raw_width) {
    AzimuthalFootprint f;
    f.valid = true;
    f.h0 = h0;
    f.raw_width = raw_width;
    f.h1 = clamp(h0 - raw_width / 2, -1.0f, 1.0f);
    f.h2 = clamp(h0 + raw_width / 2, -1.0f, 1.0f);
    f.across = Vec3(0, 1, 0);
    return f;
}

TEST(MultiscaleModes, AutoPicksByFootprint) {
    const YarnDescription d = default_yarn_description();
    const float fiber = fiber_feature_width(d);
    EXPECT_NEAR(fiber, 2 * d.fiber_radius * d.ply_radius, 1e-7f);
    // By fibers under the footprint alone (near_pixels off):
    MultiscaleSettings by_fibers = default_multiscale_settings();
    by_fibers.near_pixels = 0;
    const MultiscaleSelector auto_mode(by_fibers);
    EXPECT_EQ(auto_mode.choose(AzimuthalFootprint{}, d), MultiscaleMode::Near);  // no differentials
    EXPECT_EQ(auto_mode.choose(footprint(0.0f, 0.5f * fiber), d), MultiscaleMode::Near);
    EXPECT_EQ(auto_mode.choose(footprint(0.0f, 1.5f * fiber), d), MultiscaleMode::Multi);
    EXPECT_EQ(auto_mode.choose(footprint(0.3f, 1.9f), d), MultiscaleMode::Multi);
    EXPECT_EQ(auto_mode.choose(footprint(0.3f, 2.7f), d), MultiscaleMode::Far);  // reaches both silhouettes
    // Clamped at a silhouette, what counts is the range actually covered.
    EXPECT_EQ(auto_mode.choose(footprint(0.999f, 1.6f * fiber), d), MultiscaleMode::Near);  // 0.8 fiber
    // A pixel as wide as the yarn (far_limit 1) is far even where its footprint ends inside the yarn.
    EXPECT_EQ(auto_mode.choose(footprint(0.8f, 2.0f), d), MultiscaleMode::Far);
    MultiscaleSettings s = by_fibers;
    s.far_limit = 2;
    EXPECT_EQ(MultiscaleSelector(s).choose(footprint(0.8f, 2.0f), d), MultiscaleMode::Multi);
    s.far_limit = 0.5f;  // half a yarn per pixel
    EXPECT_EQ(MultiscaleSelector(s).choose(footprint(0.0f, 1.0f), d), MultiscaleMode::Far);
    s.footprint_scale = 2;  // the limit is per pixel, not per (scaled) footprint
    EXPECT_EQ(MultiscaleSelector(s).choose(footprint(0.0f, 1.0f), d), MultiscaleMode::Multi);
    EXPECT_FALSE(auto_mode.warned());
}

TEST(MultiscaleModes, AutoShadesYarnsManyPixelsWideNear) {
    const YarnDescription d = default_yarn_description();
    const float fiber = fiber_feature_width(d);
    const MultiscaleSettings defaults = default_multiscale_settings();
    ASSERT_EQ(defaults.near_pixels, 4.0f);
    const MultiscaleSelector auto_mode(defaults);
    // raw_width is the pixel's share of the yarn's diameter (2): a yarn 2 / raw_width pixels wide.
    EXPECT_EQ(auto_mode.choose(footprint(0.0f, 1.5f * fiber), d), MultiscaleMode::Near);  // many pixels
    EXPECT_EQ(auto_mode.choose(footprint(0.0f, 0.45f), d), MultiscaleMode::Near);  // 4.4 pixels
    EXPECT_EQ(auto_mode.choose(footprint(0.0f, 0.55f), d), MultiscaleMode::Multi);  // 3.6 pixels
    EXPECT_EQ(auto_mode.choose(footprint(0.3f, 1.9f), d), MultiscaleMode::Multi);  // about a pixel
    MultiscaleSettings s = defaults;
    s.footprint_scale = 2;  // the width is in pixels, not in (scaled) footprints
    EXPECT_EQ(MultiscaleSelector(s).choose(footprint(0.0f, 0.9f), d), MultiscaleMode::Near);
    s.near_pixels = 8;
    EXPECT_EQ(MultiscaleSelector(s).choose(footprint(0.0f, 0.9f), d), MultiscaleMode::Multi);
}

TEST(MultiscaleModes, ForcedFarWarnsOnceOnYarnsWiderThanAPixel) {
    MultiscaleSettings s = default_multiscale_settings();
    s.mode = MultiscaleMode::Far;
    std::vector<std::string> messages;
    const MultiscaleSelector far(s, [&](const std::string& m) { messages.push_back(m); });
    const YarnDescription d = default_yarn_description();
    EXPECT_EQ(far.choose(footprint(0.0f, 3.0f), d), MultiscaleMode::Far);  // pixel wider than the yarn
    EXPECT_TRUE(messages.empty());
    EXPECT_EQ(far.choose(footprint(0.0f, 0.5f), d), MultiscaleMode::Far);  // yarn 4 pixels wide
    EXPECT_EQ(far.choose(footprint(0.0f, 0.1f), d), MultiscaleMode::Far);
    ASSERT_EQ(messages.size(), 1u);
    EXPECT_NE(messages[0].find("4.0 pixels"), std::string::npos) << messages[0];
    EXPECT_TRUE(far.warned());
    // Forced near and multi never warn.
    s.mode = MultiscaleMode::Multi;
    const MultiscaleSelector multi(s, [&](const std::string& m) { messages.push_back(m); });
    EXPECT_EQ(multi.choose(footprint(0.0f, 0.1f), d), MultiscaleMode::Multi);
    EXPECT_EQ(messages.size(), 1u);
}

TEST(MultiscaleModes, SampleCountFollowsTheCoveredRange) {
    const YarnDescription d = default_yarn_description();
    MultiscaleSettings s = default_multiscale_settings();
    // The default stops at 5: more h samples cost more than they save (docs/multiscale.md).
    EXPECT_EQ(h_sample_count(2.0f, d, s), 5);
    s.max_h_samples = 16;
    const float fiber = fiber_feature_width(d);
    // One per fiber diameter, rounded up to odd (a cell centred on h0), at most 15.
    EXPECT_EQ(h_sample_count(0.0f, d, s), 1);
    EXPECT_EQ(h_sample_count(0.5f * fiber, d, s), 1);
    EXPECT_EQ(h_sample_count(2.5f * fiber, d, s), 3);
    EXPECT_EQ(h_sample_count(3.5f * fiber, d, s), 5);
    EXPECT_EQ(h_sample_count(2.0f, d, s), 15);
    EXPECT_EQ(h_sample_count(std::nanf(""), d, s), 15);
    MultiscaleSettings few = s;
    few.max_h_samples = 6;
    EXPECT_EQ(h_sample_count(2.0f, d, few), 5);
    few.sample_spacing = 2;
    EXPECT_EQ(h_sample_count(3.5f * fiber, d, few), 3);
}

TEST(MultiscaleModes, SettingsTableAndNames) {
    const MultiscaleSettings s = default_multiscale_settings();
    EXPECT_EQ(s.mode, MultiscaleMode::Auto);
    EXPECT_EQ(s.aggregation, MultiscaleAggregation::Mixture);
    EXPECT_NO_THROW(check_multiscale_settings(s, "f", "render"));
    for (const ParamInfo& info : multiscale_param_table()) {
        EXPECT_GE(*param_field(s, info), info.min_value) << info.name;
        EXPECT_LE(*param_field(s, info), info.max_value) << info.name;
        EXPECT_NE(std::string(info.doc), "") << info.name;
    }
    MultiscaleSettings bad = s;
    bad.max_h_samples = 3.5f;
    EXPECT_THROW(check_multiscale_settings(bad, "f", "render"), InputError);
    bad = s;
    bad.roughness_c = std::nanf("");
    EXPECT_THROW(check_multiscale_settings(bad, "f", "render"), InputError);
    bad = s;
    bad.max_h_samples = 17;
    EXPECT_THROW(check_multiscale_settings(bad, "f", "render"), InputError);
    for (MultiscaleMode m : {MultiscaleMode::Near, MultiscaleMode::Multi, MultiscaleMode::Far, MultiscaleMode::Auto})
        EXPECT_EQ(parse_multiscale_mode(multiscale_mode_name(m)), m);
    EXPECT_FALSE(parse_multiscale_mode("medium").has_value());
    EXPECT_EQ(parse_multiscale_aggregation("aggregate"), MultiscaleAggregation::Aggregate);
    EXPECT_FALSE(parse_multiscale_aggregation("sum").has_value());
}

TEST(MultiscaleModes, RoughnessGrowsWithTheCoveredRange) {
    const StraightYarn s;
    const MultiscaleBysdf near(s.yarn(), s.settings, s.query(0.2f, 0.0f, 38.3f, 0.5f, MultiscaleMode::Near, 0.5f));
    EXPECT_EQ(near.roughness_increase(), 0.0f);
    const MultiscaleBysdf multi(s.yarn(), s.settings, s.query(0.2f, 0.0f, 38.3f, 0.5f, MultiscaleMode::Multi, 0.5f));
    EXPECT_NEAR(multi.h2() - multi.h1(), 0.5f, 1e-4f);
    EXPECT_NEAR(multi.roughness_increase(), 0.5f / s.settings.roughness_c, 1e-5f);
    EXPECT_EQ(multi.samples(), h_sample_count(0.5f, s.description, s.settings));
    const MultiscaleBysdf far(s.yarn(), s.settings, s.query(0.2f, 0.0f, 38.3f, 0.5f, MultiscaleMode::Far, 0.5f));
    EXPECT_EQ(far.h1(), -1.0f);
    EXPECT_EQ(far.h2(), 1.0f);
    EXPECT_NEAR(far.roughness_increase(), 2.0f / s.settings.roughness_c, 1e-6f);
    // Cells clipped to [-1, 1]: K or K + 1 of them; weights are their lengths.
    EXPECT_GE(far.samples(), 15);
    EXPECT_LE(far.samples(), 16);
    float weights = 0;
    for (int k = 0; k < far.components(); ++k) {
        EXPECT_GE(far.component(k).h, -1.0f);
        EXPECT_LE(far.component(k).h, 1.0f);
        weights += far.component(k).weight;
    }
    EXPECT_NEAR(weights, 1.0f, 1e-5f);
}

TEST(MultiscaleModes, PassThroughBetweenPlies) {
    const StraightYarn s;
    // Offset 0.99: inside the tube, outside every ply.
    const MultiscaleBysdf near(s.yarn(), s.settings, s.query(0.99f, 0.0f, 38.3f, 0.0f, MultiscaleMode::Near, 0.5f));
    EXPECT_TRUE(near.empty());
    EXPECT_EQ(near.pass_fraction(), 1.0f);
    EXPECT_NEAR(near.pass_distance(), 2 * std::sqrt(1 - 0.99f * 0.99f), 1e-3f);
    EXPECT_FALSE(near.sample(Vec3(0, 0, 1), 0.5f, {0.5f, 0.5f}).has_value());
    // The same ray in the far field: most of the yarn is plies; some of it is not.
    const MultiscaleBysdf far(s.yarn(), s.settings, s.query(0.99f, 0.0f, 38.3f, 0.0f, MultiscaleMode::Far, 0.5f));
    EXPECT_FALSE(far.empty());
    EXPECT_GT(far.pass_fraction(), 0.0f);
    EXPECT_LT(far.pass_fraction(), 0.5f);
    EXPECT_NEAR(far.pass_distance(), 2 * std::sqrt(1 - 0.99f * 0.99f), 1e-3f);
    // Rays leave from the hit nearest h0 (toward the edge here).
    const Vec3 p = far.position();
    EXPECT_GT(std::fabs(p.y), 0.5f);
    EXPECT_LT(std::hypot(p.x, p.y), 1.0f);
}

TEST(MultiscaleModes, AggregateIsOneLobeInTheMeanFrame) {
    StraightYarn s;
    s.settings.aggregation = MultiscaleAggregation::Aggregate;
    const MultiscaleBysdf agg(s.yarn(), s.settings, s.query(0.0f, 0.0f, 38.3f, 0.0f, MultiscaleMode::Far, 0.5f));
    EXPECT_EQ(agg.components(), 1);
    s.settings.aggregation = MultiscaleAggregation::Mixture;
    const MultiscaleBysdf mix(s.yarn(), s.settings, s.query(0.0f, 0.0f, 38.3f, 0.0f, MultiscaleMode::Far, 0.5f));
    // Same frame and G_multi; the aggregated normal of a yarn seen from +x faces +x.
    EXPECT_NEAR(dot(agg.frame().n, mix.frame().n), 1.0f, 1e-5f);
    EXPECT_GT(agg.frame().n.x, 0.7f);
    EXPECT_NEAR(agg.fiber_shadow(), mix.fiber_shadow(), 1e-6f);
    EXPECT_GT(std::fabs(agg.frame().s.z), 0.7f);  // the mean tangent follows the yarn
    // In the near field (one h) the aggregate equals the mixture: same lobe, two-sided.
    s.settings.aggregation = MultiscaleAggregation::Aggregate;
    const MultiscaleBysdf agg_near(s.yarn(), s.settings, s.query(0.3f, 0.2f, 38.3f, 0.0f, MultiscaleMode::Near, 0.5f));
    const Vec3 wo = -StraightYarn::direction(0.2f);
    const YarnTubeHit hit = s.tube_hit(0.3f, 0.2f, 38.3f);
    for (Vec3 wi : {normalize(Vec3(1, 0.4f, 0.2f)), normalize(Vec3(-1, -0.2f, 0.4f))}) {
        const Vec3 a = model_integrand(agg_near, wo, wi), b = near_field_integrand(s, hit, wo, wi);
        EXPECT_NEAR(a.x, b.x, 2e-3f * b.x + 1e-6f);
    }
}

}  // namespace
}  // namespace purl::test
