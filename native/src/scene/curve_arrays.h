// Yarn curves from flat arrays (the Python module, the Blender add-on): the one place
// where in-memory curve data of any basis becomes YarnCurves.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "math/spline_convert.h"
#include "scene/curves.h"

namespace purl {

struct CurveArrays {
    CurveBasis basis = CurveBasis::BSpline;
    const float* points = nullptr;    // 3 per point
    const float* radii = nullptr;     // 1 per point
    size_t point_count = 0;
    const int64_t* offsets = nullptr; // curve_count + 1, non-decreasing, last == point_count
    size_t curve_count = 0;
    const uint8_t* closed = nullptr;  // optional, 1 per curve
    const int32_t* ids = nullptr;     // optional, 1 per curve
    const float* colors = nullptr;    // optional, 3 per curve: linear RGB in [0, 1] (YarnCurves::colors)
};

// Radii may taper to 0 (hair tips); no curve is thinner than this share of its largest radius.
constexpr float kThinnestRadiusShare = 1e-3f;

// Validates and converts; throws InputError naming `source` and the offending curve.
YarnCurves curves_from_arrays(const CurveArrays& arrays, const std::string& source);
CurveBasis parse_curve_basis(const std::string& name, const std::string& source);

}  // namespace purl
