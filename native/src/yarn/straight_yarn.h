// A straight yarn of radius 1 along +z, as uniform cubic B-spline control points (x, y, z,
// radius), one yarn radius apart: the yarn the far-field table is tabulated on
// (render/far_field.cpp), and the straight case of the ply validation (reference/).
#pragma once
#include <vector>

#include "math/vec.h"

namespace purl {

// 80 points: long enough that a ray at 85 degrees through the middle third stays off the ends.
inline std::vector<Vec4> straight_yarn_points(int count = 80) {
    std::vector<Vec4> points;
    points.reserve(count);
    for (int i = 0; i < count; ++i) points.emplace_back(0.0f, 0.0f, float(i), 1.0f);
    return points;
}

}  // namespace purl
