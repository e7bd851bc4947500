// Exact conversion of cubic curves (Catmull-Rom, Bezier, B-spline) and interpolation of
// polylines into uniform cubic B-spline segments, the only basis the renderer traces.
//
// Why segments and not one chain: a chain of uniform B-spline control points, where
// segment s uses points s..s+3, is C2 everywhere. A uniform Catmull-Rom curve is only C1:
// at the join after segment (p0..p3) its second derivative jumps by
// p0 - 2 p1 + 2 p3 - p4, which is zero only for special data (e.g. samples of a quadratic). Bezier splines are
// only C0 in general. So the exact representation gives each segment its own 4 control
// points (consecutive segments share none), and `segment_first` tells where each starts,
// as Embree's curve index buffer does. B-spline input and interpolated polylines are chains.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "math/vec.h"

namespace purl {

enum class CurveBasis { BSpline, CatmullRom, Bezier, Polyline };
const char* curve_basis_name(CurveBasis b);  // "B-spline", "Catmull-Rom", ... for messages

// Uniform cubic B-spline segments. Segment s uses points[segment_first[s] + 0..3], t in [0, 1].
// A chain has segment_first[s] == s; a closed chain already holds its 3 wrapped points.
struct BSplineSegments {
    std::vector<Vec4> points;  // (x, y, z, radius), same units as the input
    std::vector<uint32_t> segment_first;

    size_t segment_count() const { return segment_first.size(); }
    bool is_chain() const;
    Vec4 evaluate(size_t segment, float t) const;
};

// Converts one curve of n input points (x, y, z, radius) to B-spline segments. Radius is
// converted by the same linear map as the position. Conventions (as in BCC files):
//   BSpline:    open n >= 4 -> n-3 segments; closed n >= 3 -> n segments (points wrapped).
//   CatmullRom: open n >= 4 covers p1..p(n-2) (n-3 segments); closed n >= 3 covers the loop.
//   Bezier:     open n = 3k+1, closed n = 3k (last segment ends at p0); k segments; exact.
//   Polyline:   interpolating C2 spline through every point (natural ends when open), a chain.
// Throws std::invalid_argument for a point count the basis cannot use.
BSplineSegments to_bspline_segments(CurveBasis basis, const Vec4* points, size_t n, bool closed);

// Minimum point count for a basis (closed or open), for readers that validate input.
size_t min_points(CurveBasis basis, bool closed);
// Whether n points form whole segments in this basis (Bezier needs 3k+1 or 3k points).
bool valid_point_count(CurveBasis basis, size_t n, bool closed);

// B-spline chain control points whose curve passes through all n points, in order:
// (c[i-1] + 4 c[i] + c[i+1]) / 6 = p[i]. Open: n + 2 points, natural ends (zero curvature),
// segment i runs from p[i] to p[i+1]. Closed: n points before wrapping, segment i runs from
// p[i] to p[i+1]. Solved as a (cyclic) tridiagonal system in double precision.
std::vector<Vec4> interpolate_bspline(const Vec4* points, size_t n, bool closed);

// One segment's basis change; all exact (up to rounding), t preserved.
void catmull_rom_to_bspline(const Vec4 cr[4], Vec4 out[4]);
void bezier_to_bspline(const Vec4 bz[4], Vec4 out[4]);
void bspline_to_bezier(const Vec4 bs[4], Vec4 out[4]);

// Direct evaluation in each basis, for tests and exporters (t in [0, 1]).
Vec4 eval_catmull_rom(const Vec4 cr[4], float t);
Vec4 eval_bezier(const Vec4 bz[4], float t);
Vec4 eval_bspline(const Vec4 bs[4], float t);

}  // namespace purl
