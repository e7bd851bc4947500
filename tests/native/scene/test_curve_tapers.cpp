// Hair from Blender tapers to radius 0 at its tips: curves_from_arrays keeps such curves,
// with every B-spline control radius (hence the whole curve) positive.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "scene/curve_arrays.h"

namespace purl {
namespace {

YarnCurves tapered_hair(CurveBasis basis, int points) {
    std::vector<float> xyz, radii;
    for (int i = 0; i < points; ++i) {
        xyz.insert(xyz.end(), {0.1f * i, 0.02f * (i % 3), 0.0f});
        radii.push_back(0.01f * (1.0f - float(i) / float(points - 1)));  // 0.01 at the root, 0 at the tip
    }
    std::vector<int64_t> offsets{0, points};
    CurveArrays a;
    a.basis = basis;
    a.points = xyz.data();
    a.radii = radii.data();
    a.point_count = size_t(points);
    a.offsets = offsets.data();
    a.curve_count = 1;
    return curves_from_arrays(a, "hair");
}

TEST(CurveTapers, TaperedHairKeepsEveryRadiusPositive) {
    for (CurveBasis basis : {CurveBasis::CatmullRom, CurveBasis::Bezier, CurveBasis::BSpline, CurveBasis::Polyline}) {
        SCOPED_TRACE(int(basis));
        const YarnCurves c = tapered_hair(basis, 7);
        float thinnest = 1, thickest = 0;
        for (const Vec4& p : c.control_points) {
            thinnest = std::min(thinnest, p.w);
            thickest = std::max(thickest, p.w);
        }
        EXPECT_GE(thinnest, kThinnestRadiusShare * 0.01f * 0.999f);
        EXPECT_GT(thickest, 0.005f);  // the taper itself survives
    }
}

}  // namespace
}  // namespace purl
