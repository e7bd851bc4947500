// Uniform cubic B-splines that pass through given points: the explicit plies and fibers are
// sampled exactly (from the yarn module's helix formulas) at even steps along the yarn, and
// their control points are solved so that the curve's value at knot j is sample j. Between
// knots the curve is the C2 cubic spline interpolant, whose error for a smooth path is at most
// 5/384 h^4 max|P''''| (h = one knot step). Unlike interpolate_bspline (math/spline_convert.h),
// samples come in double precision and open ends take the slope of the cubic through the last
// four samples rather than zero curvature, which keeps fourth-order accuracy up to the ends.
#pragma once
#include <cstddef>
#include <vector>

#include "math/vec.h"

namespace purl {

// (x, y, z, radius) in double precision: the solve is done in doubles, the result rounded once.
struct Point4d {
    double v[4] = {0, 0, 0, 0};
};

// Closed loop: n >= 3 samples give n control points, laid out for YarnCurves::add_curve(...,
// closed = true), whose segment j starts at sample j. Cyclic tridiagonal solve (Sherman-Morrison).
std::vector<Vec4> interpolate_closed(const std::vector<Point4d>& samples);

// Open curve: n >= 4 samples give n + 2 control points (n - 1 segments), segment j starting at
// sample j and the last one ending at sample n - 1. End slopes (per knot step, along increasing
// j at both ends) come from the caller, or else from the cubic through the four end samples.
std::vector<Vec4> interpolate_open(const std::vector<Point4d>& samples, const Point4d* start_slope = nullptr,
                                   const Point4d* end_slope = nullptr);

// Slope per knot step at knot 0 from the path at 0, 1/2, 1, 3/2 and 2 knot steps (one-sided
// five-point rule, error ~ h^5 |P^(5)| / 80). For the far end pass the samples counted from
// the end and negate the result.
Point4d end_slope(const Point4d& p0, const Point4d& p_half, const Point4d& p1, const Point4d& p_3half,
                  const Point4d& p2);

}  // namespace purl
