// `purl deps` (scene/scene_files.h): every file a scene reads besides itself, where the scene names
// it, whether it exists and whether it travels with the scene's folder.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "base/input_error.h"
#include "scene/bcc.h"
#include "scene/scene_files.h"
#include "scene/swatch.h"

namespace purl {
namespace {

namespace fs = std::filesystem;

class SceneFilesTest : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() / ("purl_scene_files_test_" + std::to_string(::getpid()));
        fs::create_directories(root_ / "shot" / "curves");
        fs::create_directories(root_ / "library");
        SwatchOptions swatch;
        swatch.warps = swatch.wefts = 2;
        write_bcc((root_ / "shot" / "curves" / "plain.bcc").string(), generate_swatch(SwatchKind::Plain, swatch));
        write("shot/card.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        write("shot/wool.json", R"({"material": {"model": "bysdf", "eta": 1.6}})");
        write("library/cotton.json", R"({"material": {"model": "bysdf", "eta": 1.5}})");
        write("library/sky.hdr", "not read by deps");
        setenv("PURL_PRESET_PATH", (root_ / "library").string().c_str(), 1);
    }
    void TearDown() override {
        unsetenv("PURL_PRESET_PATH");
        fs::remove_all(root_);
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(root_ / name) << text; }
    // A scene in shot/ naming a BCC file, an OBJ, a preset file, a named preset and a sky texture.
    std::string write_scene(const std::string& texture) {
        write("shot/scene.json", R"({"camera": {"position": [0, -1, 0], "look_at": [0, 0, 0]},
            "world": {"texture": ")" + texture + R"("},
            "yarns": [{"bcc": "curves/plain.bcc", "radius": 0.0005, "material": {"preset_file": "wool.json"}},
                      {"generate": {"kind": "knit"}, "material": {"preset": "cotton"}}],
            "meshes": [{"obj": "card.obj"}]})");
        return (root_ / "shot" / "scene.json").string();
    }
    fs::path root_;
};

TEST_F(SceneFilesTest, ListsEveryFileWithItsPlaceInTheScene) {
    const std::string scene = write_scene((root_ / "library" / "sky.hdr").string());
    const std::vector<SceneFileStatus> files = scene_file_statuses(scene);
    ASSERT_EQ(files.size(), 6u);
    const std::vector<std::pair<std::string, std::string>> expected{
        {"scene", ""}, {"texture", "world.texture"}, {"bcc", "yarns[0].bcc"},
        {"preset_file", "yarns[0].material.preset_file"}, {"preset", "yarns[1].material.preset"}, {"obj", "meshes[0].obj"}};
    for (size_t i = 0; i < files.size(); ++i) {
        EXPECT_EQ(files[i].file.role, expected[i].first) << i;
        EXPECT_EQ(files[i].file.place, expected[i].second) << i;
        EXPECT_TRUE(files[i].exists) << files[i].file.path;
        EXPECT_EQ(files[i].bytes, fs::file_size(files[i].file.path)) << files[i].file.path;
    }
    // The scene, the BCC file, the preset file and the OBJ live in shot/; the named preset and the
    // texture come from elsewhere, so a worker needs them at the same path.
    const std::vector<bool> inside{true, false, true, true, false, true};
    for (size_t i = 0; i < files.size(); ++i) EXPECT_EQ(files[i].inside_scene_folder, inside[i]) << i;
    EXPECT_EQ(fs::path(files[4].file.path), root_ / "library" / "cotton.json");

    const std::string table = scene_files_table(scene, files);
    EXPECT_NE(table.find("6 files"), std::string::npos) << table;
    EXPECT_NE(table.find("2 outside the scene's folder, 0 missing"), std::string::npos) << table;
    EXPECT_NE(table.find("curves/plain.bcc"), std::string::npos) << table;  // relative inside the folder
    EXPECT_NE(table.find("(named preset: workers find it on their preset path)"), std::string::npos) << table;
    const nlohmann::json json = nlohmann::json::parse(scene_files_json(scene, files));
    ASSERT_EQ(json["files"].size(), 6u);
    EXPECT_EQ(json["files"][2]["path"], (root_ / "shot" / "curves" / "plain.bcc").string());
    EXPECT_EQ(json["files"][1]["inside_scene_folder"], false);
}

TEST_F(SceneFilesTest, MissingTextureIsListedThenAnErrorNamingItsPlace) {
    const std::string scene = write_scene("sky_missing.exr");
    const std::vector<SceneFileStatus> files = scene_file_statuses(scene);
    EXPECT_FALSE(files[1].exists);
    EXPECT_NE(scene_files_table(scene, files).find("missing"), std::string::npos);
    std::FILE* sink = std::tmpfile();
    try {
        run_deps_command(scene, false, sink);
        FAIL() << "a missing texture must be an error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("world.texture"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("sky_missing.exr"), std::string::npos) << e.what();
    }
    std::fclose(sink);
}

TEST_F(SceneFilesTest, MissingCurveFileStopsWithTheReaderError) {
    const std::string scene = write_scene((root_ / "library" / "sky.hdr").string());
    fs::remove(root_ / "shot" / "curves" / "plain.bcc");
    EXPECT_THROW(scene_file_statuses(scene), InputError);
}

TEST_F(SceneFilesTest, SceneWithoutFilesListsOnlyItself) {
    write("shot/generated.json", R"({"camera": {"position": [0, -1, 0], "look_at": [0, 0, 0]},
        "yarns": [{"generate": {"kind": "knit"}}]})");
    const std::vector<SceneFileStatus> files = scene_file_statuses((root_ / "shot" / "generated.json").string());
    ASSERT_EQ(files.size(), 1u);
    EXPECT_EQ(files[0].file.role, "scene");
    EXPECT_TRUE(files[0].inside_scene_folder);
}

}  // namespace
}  // namespace purl
