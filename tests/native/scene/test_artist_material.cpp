// A bysdf material's artist controls in the scene format: "color", "sheen", "softness",
// "translucency" on top of the physics parameters or a preset.
#include <gtest/gtest.h>

#include <string>

#include "base/input_error.h"
#include "bsdf/artist_params.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

BysdfParams material_of(const std::string& material) {
    const std::string text = R"({"camera": {"position": [0, -2, 0], "look_at": [0, 0, 0]},
        "film": {"width": 8, "height": 8},
        "yarns": [{"generate": {"kind": "plain"}, "material": )" + material + "}]}";
    return parse_scene_text(text, "artist.json", PURL_SOURCE_DIR "/scenes").yarns.at(0).material.bysdf;
}

TEST(ArtistMaterial, ColourOnABysdfMaterialRecoloursTheBody) {
    const BysdfParams p = material_of(R"({"model": "bysdf", "body_transmission_albedo": [0.5, 0.5, 0.5],
                                          "body_reflection_albedo": [0.2, 0.1, 0.1], "color": [1, 0, 0]})");
    EXPECT_FLOAT_EQ(p.body_transmission_albedo.x, 0.5f);
    EXPECT_FLOAT_EQ(p.body_transmission_albedo.y, 0.0f);
    EXPECT_FLOAT_EQ(p.body_reflection_albedo.x, 0.2f);
}

TEST(ArtistMaterial, ColourAppliesOnTopOfAPresetKeepingItsStrengths) {
    const BysdfParams preset = material_of(R"({"preset": "fleece"})");
    const BysdfParams red = material_of(R"({"preset": "fleece", "color": [0.9, 0.05, 0.05], "sheen": 0.5})");
    const float strength = std::max(preset.body_transmission_albedo.x,
                                    std::max(preset.body_transmission_albedo.y, preset.body_transmission_albedo.z));
    EXPECT_FLOAT_EQ(red.body_transmission_albedo.x, 0.9f * strength);
    EXPECT_FLOAT_EQ(red.body_transmission_albedo.y, 0.05f * strength);
    EXPECT_FLOAT_EQ(red.sigma_t_body, preset.sigma_t_body);
    EXPECT_FLOAT_EQ(1 - red.body_share, 0.5f * (1 - preset.body_share));
}

TEST(ArtistMaterial, BadControlsAreErrorsThatNameThePlace) {
    try {
        material_of(R"({"model": "bysdf", "color": [2, 0, 0]})");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("color"), std::string::npos) << e.what();
    }
    EXPECT_THROW(material_of(R"({"model": "bysdf", "sheen": -1})"), InputError);
    EXPECT_THROW(material_of(R"({"model": "bysdf", "softness": "soft"})"), InputError);
}

}  // namespace
}  // namespace purl
