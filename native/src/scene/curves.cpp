#include "scene/curves.h"

#include <cmath>

#include "scene/input_error.h"

namespace purl {

void validate_curves(const YarnCurves& curves, const std::string& source) {
    const size_t nc = curves.curve_count();
    if (curves.closed.size() != nc || curves.curve_ids.size() != nc)
        throw InputError(source, "curves", "per-curve arrays do not match the curve count");
    if (curves.curve_offsets.back() != curves.point_count())
        throw InputError(source, "curves", "curve offsets do not end at the point count");
    if (curves.segment_offsets.size() != nc + 1 || curves.segment_offsets.back() != curves.segment_count())
        throw InputError(source, "curves", "segment offsets do not match the segments");
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
                throw InputError(source, where, "radius must be positive and finite, got " +
                                                    std::to_string(p.w));
        }
    }
}

}  // namespace purl
