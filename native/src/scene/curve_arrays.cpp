#include "scene/curve_arrays.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/input_error.h"

namespace purl {

CurveBasis parse_curve_basis(const std::string& name, const std::string& source) {
    if (name == "bspline") return CurveBasis::BSpline;
    if (name == "catmull_rom") return CurveBasis::CatmullRom;
    if (name == "bezier") return CurveBasis::Bezier;
    if (name == "polyline") return CurveBasis::Polyline;
    throw InputError(source, "basis", "must be bspline, catmull_rom, bezier or polyline, got \"" + name + "\"");
}

YarnCurves curves_from_arrays(const CurveArrays& a, const std::string& source) {
    if (a.offsets[0] != 0) throw InputError(source, "offsets", "must start at 0");
    if (a.offsets[a.curve_count] != int64_t(a.point_count))
        throw InputError(source, "offsets", "must end at the point count (" + std::to_string(a.point_count) + ")");
    YarnCurves curves;
    std::vector<Vec4> points;
    for (size_t c = 0; c < a.curve_count; ++c) {
        const std::string place = "curve " + std::to_string(c);
        const int64_t begin = a.offsets[c], end = a.offsets[c + 1];
        if (end < begin) throw InputError(source, place, "offsets decrease");
        const bool closed = a.closed && a.closed[c];
        const size_t n = static_cast<size_t>(end - begin);
        if (!valid_point_count(a.basis, n, closed))
            throw InputError(source, place, "has " + std::to_string(n) + " points, too few or not whole segments " +
                                                "for this basis (at least " +
                                                std::to_string(min_points(a.basis, closed)) + ")");
        points.resize(n);
        float largest_radius = 0;
        for (size_t i = 0; i < n; ++i) {
            const float* p = a.points + 3 * (begin + i);
            const float r = a.radii[begin + i];
            const std::string where = place + ", point " + std::to_string(i);
            if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
                throw InputError(source, where, "position is not finite");
            if (!(r >= 0) || !std::isfinite(r))
                throw InputError(source, where, "radius must be positive and finite (0 only where a curve tapers), got " + std::to_string(r));
            points[i] = Vec4(p[0], p[1], p[2], r);
            largest_radius = std::max(largest_radius, r);
        }
        if (!(largest_radius > 0)) throw InputError(source, place, "every radius is 0");
        BSplineSegments segments = to_bspline_segments(a.basis, points.data(), n, closed);
        // Hair tapers to 0 at its tips, and the exact Catmull-Rom or Bezier -> B-spline map
        // overshoots there to negative control radii. B-spline weights are non-negative, so
        // clamping the control radii keeps the whole curve at least this thin and positive.
        const float thinnest = kThinnestRadiusShare * largest_radius;
        for (Vec4& q : segments.points) q.w = std::max(q.w, thinnest);
        const int32_t id = a.ids ? a.ids[c] : static_cast<int32_t>(c);
        curves.add(segments, closed, id);
        if (a.colors) {
            const Vec3 color(a.colors[3 * c], a.colors[3 * c + 1], a.colors[3 * c + 2]);
            check_curve_color(color, source, "curve_colors[" + std::to_string(c) + "]");
            curves.colors.push_back(color);
        }
    }
    validate_curves(curves, source);
    return curves;
}

}  // namespace purl
