// Value-level limits: radius 0 and 1e30, NaN and Inf wherever numbers enter, 10^5 plies,
// films too large to allocate, colours outside [0, 1], a zero up vector, NUL in a file name,
// a key given twice. Each is a clear InputError (or a documented clamp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/renderer.h"
#include "robustness_util.h"
#include "scene/bcc.h"
#include "scene/curve_arrays.h"
#include "scene/obj_reader.h"
#include "scene/scene_json.h"
#include "yarn/yarn_description.h"

using namespace purl;
using namespace purl::robustness;

namespace {

const std::string kCamera = R"("camera": {"position": [0, -1, 0.5], "look_at": [0, 0, 0]})";

// A 5 cm open B-spline along X, written as a BCC file.
std::string small_bcc(const ScratchDir& dir) {
    RawCurve c;
    for (int i = 0; i < 6; ++i) c.xyz.insert(c.xyz.end(), {0.01f * i, 0.002f * (i % 2), 0.0f});
    return dir.write("small.bcc", bcc_file("BS", {c}));
}

std::string scene_error(const std::string& text, const std::string& base_dir = "") {
    return input_error_of([&] { parse_scene_text(text, "scene.json", base_dir); });
}

YarnCurves arrays_curves(std::vector<float> xyz, std::vector<float> radii) {
    const int64_t offsets[2] = {0, static_cast<int64_t>(radii.size())};
    CurveArrays a;
    a.points = xyz.data();
    a.radii = radii.data();
    a.point_count = radii.size();
    a.offsets = offsets;
    a.curve_count = 1;
    return curves_from_arrays(a, "arrays");
}

}  // namespace

TEST(ValueLimits, RadiusZeroIsAnError) {
    ScratchDir dir("r0");
    const std::string bcc = small_bcc(dir);
    EXPECT_NE(input_error_of([&] { load_bcc(bcc, 0.0f); }).find("radius must be positive"), std::string::npos);
    const std::string json = "{" + kCamera + R"(, "yarns": [{"bcc": "small.bcc", "radius": 0}]})";
    // Numbers as written, not "[0.000000, ...], got 0.000000".
    EXPECT_NE(scene_error(json, dir.path().string()).find("yarns[0].radius: must be in [1e-09, 1e+30], got 0"),
              std::string::npos)
        << scene_error(json, dir.path().string());
    // In-memory arrays (Blender hair) may taper to 0; a curve with no thickness at all may not.
    EXPECT_NE(input_error_of([&] { arrays_curves({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0}, {0, 0, 0, 0}); })
                  .find("curve 0: every radius is 0"),
              std::string::npos);
    EXPECT_NE(input_error_of([&] { arrays_curves({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0}, {0.1f, -0.1f, 0.1f, 0.1f}); })
                  .find("curve 0, point 1: radius must be positive"),
              std::string::npos);
}

TEST(ValueLimits, RadiusLargerThanTheYarnSetIsAnError) {
    ScratchDir dir("r30");
    const std::string bcc = small_bcc(dir);
    // 1e30 passes the JSON range and load_bcc; the set is 5 cm across, so it cannot be meant.
    const std::string json = "{" + kCamera + R"(, "yarns": [{"bcc": "small.bcc", "radius": 1e30}]})";
    const std::string error = scene_error(json, dir.path().string());
    EXPECT_NE(error.find("radius 1e+30 is larger than the whole yarn set (bounding-box diagonal 0.05"),
              std::string::npos)
        << error;
    // Just above and just below the extent.
    const std::string over = "{" + kCamera + R"(, "yarns": [{"bcc": "small.bcc", "radius": 0.051}]})";
    EXPECT_NE(scene_error(over, dir.path().string()).find("larger than the whole yarn set"), std::string::npos);
    const std::string under = "{" + kCamera + R"(, "yarns": [{"bcc": "small.bcc", "radius": 0.049}]})";
    EXPECT_EQ(scene_error(under, dir.path().string()), "");
    // The same rule for in-memory arrays.
    EXPECT_NE(input_error_of([&] { arrays_curves({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0}, {1e30f, 1e30f, 1e30f, 1e30f}); })
                  .find("larger than the whole yarn set"),
              std::string::npos);
    // A yarn set whose points all coincide has no extent at all: said so, not blamed on the radius.
    const std::string collapsed =
        input_error_of([&] { arrays_curves(std::vector<float>(12, 0.5f), {0.1f, 0.1f, 0.1f, 0.1f}); });
    EXPECT_NE(collapsed.find("curve 0: is collapsed to one point"), std::string::npos) << collapsed;
    EXPECT_EQ(collapsed.find("radius"), std::string::npos) << collapsed;
}

TEST(ValueLimits, NonFiniteNumbersAreErrorsWherever) {
    ScratchDir dir("nan");
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    // BCC coordinates.
    for (float bad : {nan, inf, -inf}) {
        RawCurve c{{0, 0, 0, 1, 0, 0, 2, bad, 0, 3, 0, 0}};
        EXPECT_NE(input_error_of([&] { read_bcc(dir.write("bad.bcc", bcc_file("BS", {c}))); })
                      .find("curve 0, point 2 (byte 92): coordinate is not finite"),
                  std::string::npos);
    }
    // JSON has no NaN or Inf; a double too large for a float becomes infinite when read.
    EXPECT_NE(scene_error("{" + kCamera + R"(, "film": {"pixel_aspect_x": 1e39}, "meshes": [{"obj": "x"}]})")
                  .find("film.pixel_aspect_x: must be in"),
              std::string::npos);
    EXPECT_NE(scene_error(R"({"camera": {"position": [0, 1e39, 0], "look_at": [0, 0, 0]}})")
                  .find("camera.position: element 1 is not finite"),
              std::string::npos);
    // Finite numbers whose product is not: a 1e30 scale on curves 1e10 long.
    RawCurve far{{0, 0, 0, 1e10f, 0, 0, 2e10f, 1, 0, 3e10f, 0, 0}};
    dir.write("far.bcc", bcc_file("BS", {far}));
    const std::string scaled = "{" + kCamera + R"(, "yarns": [{"bcc": "far.bcc", "radius": 1,
        "matrix_world": [1e30, 0, 0, 0, 0, 1e30, 0, 0, 0, 0, 1e30, 0, 0, 0, 0, 1]}]})";
    // The scale (1e30, a float) and the radius it gives are finite; point 1 at 1e40 is not.
    EXPECT_NE(scene_error(scaled, dir.path().string()).find("curve 0, point 1: position is not finite"),
              std::string::npos)
        << scene_error(scaled, dir.path().string());
    // OBJ vertices and in-memory arrays.
    MeshDesc mesh;
    EXPECT_NE(input_error_of([&] { read_obj(dir.write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"), mesh); })
                  .find("line 2"),
              std::string::npos);
    EXPECT_NE(input_error_of([&] { read_obj(dir.write("big.obj", "v 0 0 0\nv 1 1e39 0\nv 0 1 0\nf 1 2 3\n"), mesh); })
                  .find("line 2"),
              std::string::npos);
    EXPECT_NE(input_error_of([&] { arrays_curves({0, 0, 0, 1, 0, 0, nan, 0, 0, 3, 0, 0}, {0.1f, 0.1f, 0.1f, 0.1f}); })
                  .find("point 2: position is not finite"),
              std::string::npos);
    EXPECT_NE(input_error_of([&] { arrays_curves({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0}, {0.1f, inf, 0.1f, 0.1f}); })
                  .find("point 1: radius must be positive and finite"),
              std::string::npos);
}

TEST(ValueLimits, HundredThousandPliesAreRejected) {
    const std::string json = "{" + kCamera + R"(, "yarns": [{"generate": {"kind": "plain", "warps": 2, "wefts": 2},
        "material": {"yarn": {"ply_count": 100000}}}]})";
    EXPECT_NE(scene_error(json).find("yarns[0].material.yarn.ply_count: must be in [1, 12], got 100000"),
              std::string::npos)
        << scene_error(json);
    // Descriptions built in code (Python, the add-on) meet the same check.
    YarnDescription d = default_yarn_description();
    d.ply_count = 1e5f;
    EXPECT_NE(input_error_of([&] { check_yarn_description(d, "preset.json", "yarn"); })
                  .find("preset.json: yarn.ply_count: value 100000 outside [1, 12]"),
              std::string::npos);
    d = default_yarn_description();
    d.fiber_count = 1e5f;
    EXPECT_NE(input_error_of([&] { check_yarn_description(d, "p", "yarn"); }).find("yarn.fiber_count"),
              std::string::npos);
    d = default_yarn_description();
    d.ply_count = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(input_error_of([&] { check_yarn_description(d, "p", "yarn"); }).find("yarn.ply_count"),
              std::string::npos);
}

// The JSON reader allows 32768 x 32768 (100000 x 100000 is a range error there), whose film
// and passes would be 76 GiB: the Renderer refuses it before allocating anything.
TEST(ValueLimits, FilmThatCannotBeAllocatedIsRefusedBeforeRendering) {
    SceneDesc s;
    s.camera.to_world = Transform::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0});
    s.film.width = s.film.height = 32768;
    MeshDesc m;
    m.vertices = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    const size_t rss_before = peak_resident_bytes();
    const std::string error = input_error_of([&] {
        Renderer r(s);
        RenderControl control;
        r.render(control);
    });
    EXPECT_NE(error.find("film: 32768 x 32768 pixels: a render may have 1 to 67108864 pixels"), std::string::npos)
        << error;
    EXPECT_LT(peak_resident_bytes() - rss_before, size_t(256) << 20);
    EXPECT_NE(scene_error("{" + kCamera + R"(, "film": {"width": 100000, "height": 100000}, "meshes": [{"obj": "x"}]})")
                  .find("film.width: must be in"),
              std::string::npos);
}

// Vertices are checked after matrix_world, as yarn control points are (validate_curves).
TEST(ValueLimits, MeshVerticesMadeInfiniteByTheirMatrixAreAnError) {
    const std::string json = "{" + kCamera + R"(, "meshes": [{"vertices": [[0, 0, 0], [1e30, 0, 0], [0, 1, 0]],
        "triangles": [[0, 1, 2]], "matrix_world": [1e30, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}]})";
    EXPECT_NE(scene_error(json).find("meshes[0]: vertex position is not finite (after matrix_world)"), std::string::npos)
        << scene_error(json);
}

// A literal beyond the double range ("1e400") is nlohmann's out_of_range 406, not a
// parse_error; found by fuzz_scene_json. It must be an InputError naming the place too.
TEST(ValueLimits, JsonNumberBeyondDoubleRangeIsAnInputError) {
    const std::string error = scene_error("{\"camera\": {\"position\": [0,\n 1e400, 0], \"look_at\": [0, 0, 0]}}");
    EXPECT_NE(error.find("scene.json: line 2, column 2: not valid JSON (number overflow parsing '1e400')"),
              std::string::npos)
        << error;
}

TEST(ValueLimits, InputsOnceAcceptedSilentlyAreErrors) {
    const std::string mesh = R"("meshes": [{"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]])";
    // A negative albedo made every sample invalid: a black mesh and exit 0.
    EXPECT_NE(scene_error("{" + kCamera + ", " + mesh + R"(, "color": [0.5, -0.1, 0.3]}]})")
                  .find("meshes[0].color: element 1 must be in [0, 1], got -0.1"),
              std::string::npos);
    EXPECT_NE(scene_error("{" + kCamera + ", " + mesh + R"(, "color": [1.5, 0, 0]}]})").find("got 1.5"),
              std::string::npos);
    EXPECT_NE(scene_error(R"({"camera": {"position": [0, -1, 0.5], "look_at": [0, 0, 0], "up": [0, 0, 0]}, )" + mesh +
                          "}]}")
                  .find("camera.up: has zero length"),
              std::string::npos);
    // The system would open "a" instead of "a\0.obj".
    EXPECT_NE(scene_error("{" + kCamera + R"(, "meshes": [{"obj": "a\u0000.obj"}]})")
                  .find("meshes[0].obj: contains a NUL character"),
              std::string::npos);
    // nlohmann keeps the last of two equal keys: the first setting was lost without a word.
    EXPECT_NE(scene_error("{" + kCamera + ", " + mesh + R"(, "color": [1, 0, 0], "color": [0, 1, 0]}]})")
                  .find("scene.json: meshes[0].color: given twice in the same object"),
              std::string::npos)
        << scene_error("{" + kCamera + ", " + mesh + R"(, "color": [1, 0, 0], "color": [0, 1, 0]}]})");
    EXPECT_NE(scene_error("{" + kCamera + ", " + kCamera + "}").find("scene.json: camera: given twice"),
              std::string::npos);
    EXPECT_NE(scene_error("{" + kCamera + R"(, "lights": [{}, {"type": "point", "type": "sun"}], )" + mesh + "}]}")
                  .find("lights[1].type: given twice"),
              std::string::npos);
}
