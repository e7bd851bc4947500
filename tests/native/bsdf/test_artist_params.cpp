// The artist controls' rules (bsdf/artist_params.h): neutral at their defaults, and each moves
// only what its rule says.
#include <gtest/gtest.h>

#include <cstring>

#include "bsdf/artist_params.h"

namespace purl {
namespace {

bool same(const BysdfParams& a, const BysdfParams& b) { return std::memcmp(&a, &b, sizeof(BysdfParams)) == 0; }

TEST(ArtistControls, TableDefaultsAreNeutral) {
    ArtistControls controls;
    apply_defaults(controls, artist_param_table());
    const BysdfParams p = default_bysdf_params();
    EXPECT_TRUE(same(apply_artist_controls(p, controls), p));
    for (const ParamInfo& info : artist_param_table()) EXPECT_NE(info.label, nullptr) << info.name;
}

TEST(ArtistControls, ColourReplacesTheHueAndKeepsEachLobesStrength) {
    BysdfParams p = default_bysdf_params();
    p.body_reflection_albedo = Vec3(0.1f, 0.3f, 0.2f);
    p.body_transmission_albedo = Vec3(0.6f, 0.9f, 0.3f);
    ArtistControls a;
    a.has_color = true;
    a.color = Vec3(1.0f, 0.1f, 0.0f);
    const BysdfParams q = apply_artist_controls(p, a);
    EXPECT_FLOAT_EQ(q.body_reflection_albedo.x, 0.3f);  // strength: the largest channel, 0.3
    EXPECT_FLOAT_EQ(q.body_reflection_albedo.y, 0.03f);
    EXPECT_FLOAT_EQ(q.body_transmission_albedo.x, 0.9f);
    EXPECT_FLOAT_EQ(q.body_transmission_albedo.z, 0.0f);
    EXPECT_EQ(q.specular_reflection_albedo.x, p.specular_reflection_albedo.x);  // specular untouched
    EXPECT_EQ(q.body_share, p.body_share);
    a.has_color = false;  // a colour that is not switched on does nothing
    EXPECT_TRUE(same(apply_artist_controls(p, a), p));
}

TEST(ArtistControls, SheenMovesEnergyBetweenBodyAndSpecular) {
    BysdfParams p = default_bysdf_params();
    p.body_share = 0.6f;
    ArtistControls a;
    a.sheen = 0.0f;
    EXPECT_FLOAT_EQ(apply_artist_controls(p, a).body_share, 1.0f);  // matte
    a.sheen = 2.0f;
    EXPECT_FLOAT_EQ(apply_artist_controls(p, a).body_share, 0.2f);
    a.sheen = 10.0f;
    EXPECT_FLOAT_EQ(apply_artist_controls(p, a).body_share, 0.0f);  // capped: all specular
}

TEST(ArtistControls, SoftnessScalesTheReflectionRoughnessWithinItsRange) {
    const BysdfParams p = default_bysdf_params();  // 0.2 along, 0.3 across
    ArtistControls a;
    a.softness = 2.0f;
    const BysdfParams q = apply_artist_controls(p, a);
    EXPECT_FLOAT_EQ(q.specular_roughness_along, 0.4f);
    EXPECT_FLOAT_EQ(q.specular_roughness_across, 0.6f);
    EXPECT_EQ(q.transmission_roughness, p.transmission_roughness);
    a.softness = 0.0f;
    EXPECT_FLOAT_EQ(apply_artist_controls(p, a).specular_roughness_along, 0.001f);
}

TEST(ArtistControls, TranslucencyScalesTheForwardShareAndTheExtinction) {
    BysdfParams p = default_bysdf_params();  // r0 0.5, sigma_t_body 0.2
    ArtistControls a;
    a.translucency = 1.5f;
    BysdfParams q = apply_artist_controls(p, a);
    EXPECT_FLOAT_EQ(q.body_reflection_share, 0.25f);
    EXPECT_NEAR(q.sigma_t_body, 0.2f / 1.5f, 1e-6f);
    a.translucency = 0.0f;  // opaque
    q = apply_artist_controls(p, a);
    EXPECT_FLOAT_EQ(q.body_reflection_share, 1.0f);
    EXPECT_FLOAT_EQ(q.sigma_t_body, 1000.0f);
}

}  // namespace
}  // namespace purl
