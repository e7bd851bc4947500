// validate_curves: what the renderer relies on, each broken in turn.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "base/input_error.h"
#include "math/spline_convert.h"
#include "scene/curves.h"

namespace purl {
namespace {

// Two curves: an open chain of 5 points and a closed Catmull-Rom loop converted to segments.
YarnCurves valid_curves() {
    YarnCurves y;
    std::vector<Vec4> chain, loop;
    for (int i = 0; i < 5; ++i) chain.emplace_back(float(i), 0.0f, 0.0f, 0.1f);
    for (int i = 0; i < 4; ++i) loop.emplace_back(std::cos(float(i)), std::sin(float(i)), 1.0f, 0.1f);
    y.add_curve(chain.data(), chain.size(), false);
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, loop.data(), loop.size(), true);
    y.add_curve_segments(seg.points.data(), seg.segment_count(), true, 5);
    return y;
}

void expect_invalid(const YarnCurves& y, const std::string& place_part, const std::string& reason_part) {
    try {
        validate_curves(y, "test.json");
        ADD_FAILURE() << "accepted; wanted: " << reason_part;
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "test.json");
        EXPECT_NE(e.place().find(place_part), std::string::npos) << e.what();
        EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
    }
}

TEST(ValidateCurves, AcceptsChainsAndSegments) {
    const YarnCurves y = valid_curves();
    EXPECT_NO_THROW(validate_curves(y, "test.json"));
    EXPECT_EQ(y.segment_count(0), 2u);
    EXPECT_EQ(y.segment_count(1), 4u);
    EXPECT_EQ(y.curve_ids[1], 5);
}

TEST(ValidateCurves, RejectsMismatchedArrays) {
    YarnCurves y = valid_curves();
    y.closed.pop_back();
    expect_invalid(y, "curves", "per-curve arrays");
    y = valid_curves();
    y.curve_ids.push_back(3);
    expect_invalid(y, "curves", "per-curve arrays");
    y = valid_curves();
    y.control_points.emplace_back(0.0f, 0.0f, 0.0f, 1.0f);
    expect_invalid(y, "curves", "do not end at the point count");
    y = valid_curves();
    y.segment_offsets.back() -= 1;
    expect_invalid(y, "curves", "segment offsets");
}

TEST(ValidateCurves, RejectsCurvesWithoutSegments) {
    YarnCurves y;
    const Vec4 p[3] = {{0, 0, 0, 1}, {1, 0, 0, 1}, {2, 0, 0, 1}};
    y.add_curve(p, 3, false);  // 3 points of an open chain make no segment
    expect_invalid(y, "curve 0", "at least 4");
}

TEST(ValidateCurves, RejectsSegmentsOutsideTheirCurve) {
    YarnCurves y = valid_curves();
    y.segment_first[1] = y.curve_offsets[1] - 2;  // reaches past the end of curve 0
    expect_invalid(y, "curve 0", "reaches outside");
    y = valid_curves();
    y.segment_first[y.segment_offsets[1]] = 0;  // curve 1's first segment starts in curve 0
    expect_invalid(y, "curve 1", "reaches outside");
}

TEST(ValidateCurves, RejectsBadPointsAndRadii) {
    YarnCurves y = valid_curves();
    y.control_points[2].y = std::numeric_limits<float>::quiet_NaN();
    expect_invalid(y, "curve 0, point 2", "not finite");
    y = valid_curves();
    y.control_points[y.curve_offsets[1] + 3].z = std::numeric_limits<float>::infinity();
    expect_invalid(y, "curve 1, point 3", "not finite");
    y = valid_curves();
    y.control_points[1].w = 0.0f;
    expect_invalid(y, "curve 0, point 1", "radius must be positive");
    y = valid_curves();
    y.control_points[1].w = -0.5f;
    expect_invalid(y, "point 1", "radius must be positive");
    y = valid_curves();
    y.control_points[4].w = std::numeric_limits<float>::quiet_NaN();
    expect_invalid(y, "point 4", "radius must be positive and finite");
    y = valid_curves();
    y.control_points[4].w = std::numeric_limits<float>::infinity();
    expect_invalid(y, "point 4", "radius must be positive and finite");
}

}  // namespace
}  // namespace purl
