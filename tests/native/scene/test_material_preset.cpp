// "material": {"preset": ...} and {"preset_file": ...} in scenes (scene/material_preset.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "base/input_error.h"
#include "scene/material_preset.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

namespace fs = std::filesystem;

class MaterialPresetTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("purl_preset_test_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        write("wool.json", R"({"name": "wool", "material": {"model": "bysdf", "eta": 1.6,
            "body_reflection_albedo": [0.5, 0.4, 0.3], "yarn": {"ply_count": 2, "fiber_count": 30}}})");
        write("broken.json", R"({"material": {"model": "bysdf", "etta": 1.6}})");
        write("nomaterial.json", R"({"name": "x"})");
        setenv("PURL_PRESET_PATH", dir_.string().c_str(), 1);
    }
    void TearDown() override {
        unsetenv("PURL_PRESET_PATH");
        fs::remove_all(dir_);
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    SceneDesc scene_with(const std::string& material) {
        const std::string text = R"({"camera": {"position": [0, -1, 0], "look_at": [0, 0, 0]},
            "yarns": [{"generate": {"kind": "plain", "warps": 2, "wefts": 2}, "material": )" + material + "}]}";
        return parse_scene_text(text, "scene.json", dir_.string());
    }
    fs::path dir_;
};

TEST_F(MaterialPresetTest, NamedPresetWithOverrides) {
    const MaterialDesc m = scene_with(R"({"preset": "wool", "eta": 1.3, "yarn": {"fiber_count": 12}})").yarns[0].material;
    EXPECT_FLOAT_EQ(m.bysdf.eta, 1.3f);                        // the scene's key wins
    EXPECT_FLOAT_EQ(m.bysdf.body_reflection_albedo.y, 0.4f);   // from the preset
    EXPECT_EQ(int(m.yarn.ply_count), 2);                       // nested objects merge key by key
    EXPECT_EQ(int(m.yarn.fiber_count), 12);
}

TEST_F(MaterialPresetTest, PresetFileRelativeToTheScene) {
    const MaterialDesc m = scene_with(R"({"preset_file": "wool.json"})").yarns[0].material;
    EXPECT_FLOAT_EQ(m.bysdf.eta, 1.6f);
}

TEST_F(MaterialPresetTest, FiberModelKeepsItsOwnPresets) {
    const MaterialDesc m = scene_with(R"({"model": "fiber", "preset": "silk"})").yarns[0].material;
    EXPECT_EQ(m.model, MaterialModel::Fiber);
}

TEST_F(MaterialPresetTest, ClearErrors) {
    auto error_of = [&](const std::string& material) {
        try {
            scene_with(material);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error_of(R"({"preset": "nylon"})").find("yarns[0].material.preset: no preset \"nylon\""),
              std::string::npos) << error_of(R"({"preset": "nylon"})");
    EXPECT_NE(error_of(R"({"preset": "nylon"})").find("wool"), std::string::npos);  // lists known presets
    EXPECT_NE(error_of(R"({"preset": "../wool"})").find("not a preset name"), std::string::npos);
    EXPECT_NE(error_of(R"({"preset": 3})").find("must be a preset name"), std::string::npos);
    // A mistake inside the preset names the preset file.
    EXPECT_NE(error_of(R"({"preset": "broken"})").find("broken.json: material.etta: unknown key"),
              std::string::npos) << error_of(R"({"preset": "broken"})");
    EXPECT_NE(error_of(R"({"preset_file": "nomaterial.json"})").find("needs a \"material\" object"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"preset_file": "absent.json"})").find("does not exist"), std::string::npos);
    EXPECT_NE(error_of(R"({"preset": "wool", "preset_file": "wool.json"})").find("not both"), std::string::npos);
    // Overrides are checked like any material key.
    EXPECT_NE(error_of(R"({"preset": "wool", "etta": 2})").find("etta"), std::string::npos);
}

TEST(MaterialPresetDirs, RepositoryPresetsAreSearched) {
    const std::vector<std::string> dirs = material_preset_dirs();
    ASSERT_FALSE(dirs.empty());
    EXPECT_EQ(fs::path(dirs.back()).filename(), "presets");
}

}  // namespace
}  // namespace purl
