// The JSON scene reader: what it fills in, and the message for each kind of bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/input_error.h"
#include "scene/scene_json.h"

using namespace purl;

namespace {

const char* kPlane = R"("meshes": [{"vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,2]]}])";

std::string scene_with(const std::string& camera, const std::string& rest = "") {
    return std::string("{\"camera\": ") + camera + ", " + kPlane + (rest.empty() ? "" : ", " + rest) + "}";
}

const std::string kCamera = R"({"position": [0, -5, 1], "look_at": [0, 0, 0]})";

// The message of the InputError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text) {
    try {
        parse_scene_text(text, "s.json", "");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SceneJson, ReadsEverySection) {
    const SceneDesc s = parse_scene_text(scene_with(R"({"matrix_world": [1,0,0,1, 0,1,0,2, 0,0,1,3, 0,0,0,1],
        "lens": 35, "sensor_fit": "vertical", "shift_x": 0.1, "clip_start": 0.01, "clip_end": 50})",
        R"("film": {"width": 320, "height": 200, "transparent": true},
           "render": {"spp": 16, "seed": 5, "max_depth": 4},
           "world": {"color": [0.1, 0.2, 0.3], "strength": 2},
           "lights": [{"type": "spot", "position": [0,0,3], "look_at": [0,0,0], "power": 500,
                       "radius": 0.1, "spot_size": 0.8, "spot_blend": 0.3},
                      {"type": "area", "shape": "ELLIPSE", "size": 2, "size_y": 1,
                       "position": [0,0,3], "look_at": [0,0,0]},
                      {"type": "sun", "strength": 3, "angle": 0.01, "position": [0,0,1], "look_at": [0,0,0]}])"),
        "s.json", "");
    EXPECT_FLOAT_EQ(s.camera.lens_mm, 35);
    EXPECT_EQ(s.camera.sensor_fit, SensorFit::Vertical);
    EXPECT_FLOAT_EQ(s.camera.to_world.translation().z, 3);
    EXPECT_EQ(s.film.width, 320);
    EXPECT_TRUE(s.film.transparent);
    EXPECT_EQ(s.render.spp, 16);
    EXPECT_EQ(s.render.seed, 5u);
    EXPECT_FLOAT_EQ(s.world.color.z * s.world.strength, 0.6f);
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, LightType::Spot);
    EXPECT_FLOAT_EQ(s.lights[0].spot_blend, 0.3f);
    EXPECT_EQ(s.lights[1].shape, AreaShape::Ellipse);
    EXPECT_FLOAT_EQ(s.lights[1].size_y, 1.0f);
    EXPECT_FLOAT_EQ(s.lights[2].strength, 3.0f);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].indices.size(), 3u);
}

TEST(SceneJson, LookAtPointsTheCameraDownMinusZ) {
    const SceneDesc s = parse_scene_text(scene_with(kCamera), "s.json", "");
    const Vec3 forward = -normalize(s.camera.to_world.column(2));
    const Vec3 expected = normalize(Vec3(0, 5, -1));
    EXPECT_NEAR(dot(forward, expected), 1.0f, 1e-6f);
    EXPECT_GT(s.camera.to_world.column(1).z, 0.0f);  // up stays up
}

TEST(SceneJson, ErrorsNameTheFileThePlaceAndTheReason) {
    EXPECT_EQ(error_of(scene_with(kCamera, R"("film": {"widht": 10})")), "s.json: film.widht: unknown key");
    EXPECT_EQ(error_of(scene_with(kCamera, R"("film": {"width": "10"})")),
              "s.json: film.width: must be an integer, got a string");
    EXPECT_NE(error_of(scene_with(kCamera, R"("film": {"width": 0})")).find("film.width: must be in [1"),
              std::string::npos);
    EXPECT_EQ(error_of(scene_with(kCamera, R"("lights": [{"type": "laser", "position": [0,0,1], "look_at": [0,0,0]}])")),
              "s.json: lights[0].type: must be one of point, spot, sun, area, got \"laser\"");
    EXPECT_EQ(error_of(std::string("{") + kPlane + "}"), "s.json: camera: is required");
    EXPECT_EQ(error_of(scene_with(R"({"position": [0,0,1]})")), "s.json: camera.look_at: is required with position");
    EXPECT_EQ(error_of(scene_with(R"({"position": [0,0,1], "look_at": [0,0,1]})")),
              "s.json: camera.look_at: equals position");
    EXPECT_EQ(error_of(scene_with(R"({"position": [0,0,1], "look_at": [0,0,0], "clip_start": 5, "clip_end": 1})")),
              "s.json: camera.clip_end: must be greater than clip_start");
    EXPECT_EQ(error_of(R"({"camera": )" + kCamera + "}"), "s.json: the scene has no yarns and no meshes");
    EXPECT_EQ(error_of("{\"camera\": ").rfind("s.json: line 1, column 12: not valid JSON (syntax error", 0), 0u);
    EXPECT_EQ(error_of("{\n  \"camera\": {,}}").rfind("s.json: line 2, column 14: not valid JSON", 0), 0u);
    EXPECT_EQ(error_of(scene_with(kCamera, R"("world": {"color": [1, 2]})")),
              "s.json: world.color: must be an array of 3 numbers");
}

TEST(SceneJson, MeshProblemsAreErrors) {
    const std::string cam = R"({"camera": )" + kCamera + ", ";
    EXPECT_EQ(error_of(cam + R"("meshes": [{"vertices": [[0,0,0]], "triangles": [[0,1,2]]}]})"),
              "s.json: meshes[0]: triangle index out of range");
    EXPECT_EQ(error_of(cam + R"("meshes": [{"obj": "/no/such/file.obj"}]})"), "/no/such/file.obj: cannot open file");
    EXPECT_EQ(error_of(cam + R"("yarns": [{"arrays": "x"}]})"),
              "s.json: yarns[0].arrays: names in-memory arrays, but none were given");
    EXPECT_EQ(error_of(cam + R"("yarns": [{"bcc": "a.bcc", "generate": {}}]})"),
              "s.json: yarns[0]: needs exactly one of bcc, arrays, generate");
}

TEST(SceneJson, ReadsObjFilesRelativeToTheScene) {
    const auto dir = std::filesystem::temp_directory_path() / "purl_scene_json_test";
    std::filesystem::create_directories(dir);
    {
        std::ofstream obj(dir / "quad.obj");
        obj << "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n";
        std::ofstream bad(dir / "bad.obj");
        bad << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
        std::ofstream scene(dir / "scene.json");
        scene << R"({"camera": )" << kCamera << R"(, "meshes": [{"obj": "quad.obj", "color": [0.2, 0.4, 0.6]}]})";
    }
    const SceneDesc s = load_scene_file((dir / "scene.json").string());
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].indices.size(), 6u);  // the quad fanned into two triangles
    EXPECT_FLOAT_EQ(s.meshes[0].color.y, 0.4f);
    try {
        parse_scene_text(R"({"camera": )" + kCamera + R"(, "meshes": [{"obj": "bad.obj"}]})", "s.json", dir.string());
        FAIL() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "bad.obj").string() + ": line 3: face index 7 out of range");
    }
    std::filesystem::remove_all(dir);
}

TEST(SceneJson, ReadsThePlyMethod) {
    EXPECT_EQ(parse_scene_text(scene_with(kCamera), "s.json", "").render.ply_method, PlyCrossSection::elliptical);
    for (const auto& [name, method] : {std::pair{"elliptical", PlyCrossSection::elliptical},
                                       std::pair{"local", PlyCrossSection::local},
                                       std::pair{"circular", PlyCrossSection::circular}}) {
        const std::string render = std::string(R"("render": {"ply_method": ")") + name + R"("})";
        EXPECT_EQ(parse_scene_text(scene_with(kCamera, render), "s.json", "").render.ply_method, method) << name;
    }
    EXPECT_NE(error_of(scene_with(kCamera, R"("render": {"ply_method": "exact"})")).find("render.ply_method"),
              std::string::npos);
}

TEST(SceneJson, ReadsTheExplicitModelsOptions) {
    const SceneDesc defaults = parse_scene_text(scene_with(kCamera), "s.json", "");
    EXPECT_EQ(defaults.render.model, YarnModel::Bysdf);
    EXPECT_FLOAT_EQ(defaults.render.explicit_options.ply_tolerance, ExplicitOptions{}.ply_tolerance);

    const SceneDesc s = parse_scene_text(scene_with(kCamera, R"("render": {"model": "fiber", "explicit":
        {"ply_tolerance": 0.01, "fiber_tolerance": 0.2, "curvature_quantile": 1, "memory_budget_gib": 0.5}})"),
        "s.json", "");
    EXPECT_EQ(s.render.model, YarnModel::Fiber);
    EXPECT_FLOAT_EQ(s.render.explicit_options.ply_tolerance, 0.01f);
    EXPECT_FLOAT_EQ(s.render.explicit_options.fiber_tolerance, 0.2f);
    EXPECT_FLOAT_EQ(s.render.explicit_options.curvature_quantile, 1.0f);
    EXPECT_DOUBLE_EQ(s.render.explicit_options.memory_budget_bytes, 0.5 * 1024 * 1024 * 1024);

    EXPECT_EQ(error_of(scene_with(kCamera, R"("render": {"explicit": {"tolerance": 1}})")),
              "s.json: render.explicit.tolerance: unknown key");
    EXPECT_NE(error_of(scene_with(kCamera, R"("render": {"explicit": {"curvature_quantile": 0.1}})"))
                  .find("render.explicit.curvature_quantile: must be in [0.5"),
              std::string::npos);
}
