// Per-yarn colours (YarnCurves::colors): from flat arrays and from scene JSON, the checks on
// them, and the rule that recolours a material (with_body_color).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "base/input_error.h"
#include "bsdf/bysdf_params.h"
#include "scene/curve_arrays.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

void expect_color(Vec3 a, Vec3 b) {
    EXPECT_FLOAT_EQ(a.x, b.x);
    EXPECT_FLOAT_EQ(a.y, b.y);
    EXPECT_FLOAT_EQ(a.z, b.z);
}

// Two open polylines of 4 points, as the Python module hands them over.
struct TwoCurves {
    std::vector<float> points, radii;
    std::vector<int64_t> offsets{0, 4, 8};
    std::vector<float> colors{0.9f, 0.1f, 0.2f, 0.0f, 0.5f, 1.0f};
    TwoCurves() {
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < 4; ++i) {
                points.insert(points.end(), {float(i), float(c), 0.0f});
                radii.push_back(0.1f);
            }
    }
    CurveArrays arrays() const {
        CurveArrays a;
        a.basis = CurveBasis::Polyline;
        a.points = points.data();
        a.radii = radii.data();
        a.point_count = radii.size();
        a.offsets = offsets.data();
        a.curve_count = 2;
        a.colors = colors.data();
        return a;
    }
};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(CurveColors, ArraysArriveOnePerCurve) {
    const TwoCurves t;
    const YarnCurves c = curves_from_arrays(t.arrays(), "<arrays>: knit");
    ASSERT_EQ(c.colors.size(), 2u);
    expect_color(c.colors[0], Vec3(0.9f, 0.1f, 0.2f));
    expect_color(c.colors[1], Vec3(0.0f, 0.5f, 1.0f));
    CurveArrays none = t.arrays();
    none.colors = nullptr;
    EXPECT_FALSE(curves_from_arrays(none, "<arrays>: knit").has_colors());
}

TEST(CurveColors, BadArrayColoursNameTheCurve) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), -0.1f, 1.5f, std::numeric_limits<float>::infinity()}) {
        TwoCurves t;
        t.colors[4] = bad;  // curve 1, green
        const std::string e = error_of([&] { curves_from_arrays(t.arrays(), "<arrays>: knit"); });
        EXPECT_NE(e.find("<arrays>: knit"), std::string::npos) << e;
        EXPECT_NE(e.find("curve_colors[1]"), std::string::npos) << e;
        EXPECT_NE(e.find("[0, 1]"), std::string::npos) << e;
    }
}

TEST(CurveColors, ValidateRejectsAWrongCount) {
    YarnCurves c = curves_from_arrays(TwoCurves().arrays(), "x");
    c.colors.pop_back();
    const std::string e = error_of([&] { validate_curves(c, "scene.json"); });
    EXPECT_NE(e.find("1 colours for 2 curves"), std::string::npos) << e;
}

// A generated knit swatch; `colors` is the yarn object's "curve_colors" value (empty: none).
std::string scene_with(const std::string& colors) {
    return R"({"camera": {"position": [0, -2, 0], "look_at": [0, 0, 0]},
               "yarns": [{"generate": {"kind": "knit", "courses": 2, "wales": 2})" +
           (colors.empty() ? std::string() : ", \"curve_colors\": " + colors) + "}]}";
}

TEST(CurveColors, SceneJsonTakesOneColourPerCurve) {
    const size_t n = parse_scene_text(scene_with(""), "probe.json", "").yarns.at(0).curves.curve_count();
    ASSERT_GE(n, 2u);
    std::string list = "[";
    for (size_t c = 0; c < n; ++c) list += std::string(c ? ", " : "") + (c % 2 ? "[0, 0, 1]" : "[1, 0.5, 0]");
    list += "]";
    const SceneDesc s = parse_scene_text(scene_with(list), "knit.json", "");
    const YarnCurves& curves = s.yarns.at(0).curves;
    ASSERT_EQ(curves.colors.size(), n);
    expect_color(curves.colors[0], Vec3(1.0f, 0.5f, 0.0f));
    expect_color(curves.colors[1], Vec3(0.0f, 0.0f, 1.0f));

    const std::string count = error_of([&] { parse_scene_text(scene_with("[[1, 0, 0]]"), "knit.json", ""); });
    EXPECT_NE(count.find("knit.json"), std::string::npos) << count;
    EXPECT_NE(count.find("curve_colors"), std::string::npos) << count;
    EXPECT_NE(count.find("one per curve"), std::string::npos) << count;

    std::string bad = "[[2, 0, 0]";
    for (size_t c = 1; c < n; ++c) bad += ", [0, 0, 0]";
    bad += "]";
    const std::string range = error_of([&] { parse_scene_text(scene_with(bad), "knit.json", ""); });
    EXPECT_NE(range.find("yarns[0].curve_colors[0]"), std::string::npos) << range;
    EXPECT_NE(range.find("[0, 1]"), std::string::npos) << range;

    const std::string shape = error_of([&] { parse_scene_text(scene_with("[[1, 0]" + bad.substr(10)), "knit.json", ""); });
    EXPECT_NE(shape.find("three numbers"), std::string::npos) << shape;
}

TEST(CurveColors, ColourReplacesTheBodyHueAndKeepsEachLobesStrength) {
    BysdfParams p = default_bysdf_params();
    p.body_reflection_albedo = Vec3(0.05f, 0.02f, 0.0f);
    p.body_transmission_albedo = Vec3(0.1f, 0.3f, 0.2f);
    const BysdfParams q = with_body_color(p, Vec3(0.0f, 0.5f, 1.0f));
    EXPECT_FLOAT_EQ(q.body_reflection_albedo.z, 0.05f);  // blue on a material with no blue at all
    EXPECT_FLOAT_EQ(q.body_reflection_albedo.y, 0.025f);
    EXPECT_FLOAT_EQ(q.body_reflection_albedo.x, 0.0f);
    EXPECT_FLOAT_EQ(q.body_transmission_albedo.z, 0.3f);
    EXPECT_FLOAT_EQ(q.body_transmission_albedo.y, 0.15f);
    // Everything else, ply colours and specular albedos included, is the material's.
    expect_color(q.specular_reflection_albedo, p.specular_reflection_albedo);
    expect_color(q.ply_colors[0], p.ply_colors[0]);
    EXPECT_EQ(q.eta, p.eta);
}

}  // namespace
}  // namespace purl
