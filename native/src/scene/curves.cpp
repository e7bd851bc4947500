#include "scene/curves.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "base/input_error.h"
#include "math/number_text.h"

namespace purl {

void check_curve_color(Vec3 color, const std::string& source, const std::string& place) {
    for (int k = 0; k < 3; ++k)
        if (!(color[k] >= 0.0f && color[k] <= 1.0f))  // also false for NaN
            throw InputError(source, place, "colour must be linear RGB with every channel in [0, 1], got (" +
                                                number_text(color.x) + ", " + number_text(color.y) + ", " +
                                                number_text(color.z) + ")");
}

void validate_curves(const YarnCurves& curves, const std::string& source) {
    const size_t nc = curves.curve_count();
    if (curves.closed.size() != nc || curves.curve_ids.size() != nc)
        throw InputError(source, "curves", "per-curve arrays do not match the curve count");
    if (curves.curve_offsets.back() != curves.point_count())
        throw InputError(source, "curves", "curve offsets do not end at the point count");
    if (curves.segment_offsets.size() != nc + 1 || curves.segment_offsets.back() != curves.segment_count())
        throw InputError(source, "curves", "segment offsets do not match the segments");
    if (curves.has_colors()) {
        if (curves.colors.size() != nc)
            throw InputError(source, "curve_colors", "has " + std::to_string(curves.colors.size()) +
                                                         " colours for " + std::to_string(nc) + " curves");
        for (size_t c = 0; c < nc; ++c) check_curve_color(curves.colors[c], source, "curve " + std::to_string(c));
    }
    // Radii are checked against the set's extent below, after every position is known finite.
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    float max_radius = 0.0f;
    size_t max_radius_curve = 0;
    for (size_t c = 0; c < nc; ++c) {
        const uint32_t begin = curves.curve_offsets[c], end = curves.curve_offsets[c + 1];
        const std::string place = "curve " + std::to_string(c);
        if (end < begin) throw InputError(source, place, "curve offsets decrease");
        if (curves.segment_count(c) == 0)
            throw InputError(source, place,
                             "has " + std::to_string(end - begin) +
                                 " B-spline control points; a yarn needs at least 4");
        for (uint32_t s = curves.segment_offsets[c]; s < curves.segment_offsets[c + 1]; ++s)
            if (curves.segment_first[s] < begin || curves.segment_first[s] + 4 > end)
                throw InputError(source, place, "segment " + std::to_string(s) + " reaches outside the curve");
        for (uint32_t i = begin; i < end; ++i) {
            const Vec4& p = curves.control_points[i];
            const std::string where = place + ", point " + std::to_string(i - begin);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw InputError(source, where, "position is not finite");
            if (!(p.w > 0.0f) || !std::isfinite(p.w))
                throw InputError(source, where, "radius must be positive and finite, got " + number_text(p.w));
            lo = min(lo, p.xyz());
            hi = max(hi, p.xyz());
            if (p.w > max_radius) {
                max_radius = p.w;
                max_radius_curve = c;
            }
        }
    }
    // A yarn thicker than the whole set of centre-lines is a unit mistake (a radius in mm on
    // curves in m), and radii like 1e30 leave Embree's bounds and hit distances meaningless.
    // Compared in double: the extent of finite floats can overflow a float.
    if (nc > 0) {
        const double dx = double(hi.x) - lo.x, dy = double(hi.y) - lo.y, dz = double(hi.z) - lo.z;
        const double extent = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (extent == 0)  // not a radius problem: there is no curve to put it on
            throw InputError(source, nc == 1 ? "curve 0" : "every curve",
                             "is collapsed to one point (all its control points are equal): nothing to render");
        if (max_radius > extent)
            throw InputError(source, "curve " + std::to_string(max_radius_curve),
                             "radius " + number_text(max_radius) +
                                 " is larger than the whole yarn set (bounding-box diagonal " +
                                 number_text(extent) + "); check the radius and its units");
    }
}

}  // namespace purl
