// Yarn centre-lines as Embree consumes them: uniform cubic B-spline control points
// with a per-point radius, curves stored back to back.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "math/spline_convert.h"
#include "math/vec.h"

namespace purl {

struct YarnCurves {
    // (x, y, z, radius) per control point. A closed loop of n points is stored with its
    // first three points repeated at the end (n + 3 points), so every curve is a plain
    // run of consecutive points.
    std::vector<Vec4> control_points;
    // curve_offsets[c] .. curve_offsets[c+1] are the control points of curve c (size curves + 1).
    std::vector<uint32_t> curve_offsets{0};
    // Every cubic segment as the index of its first control point (it uses that point and
    // the next three); segment_offsets[c] .. segment_offsets[c+1] are curve c's segments.
    // A chain of n points has n - 3 overlapping segments; a curve converted exactly from
    // Catmull-Rom or Bezier (C1, not C2) has 4 points of its own per segment.
    std::vector<uint32_t> segment_first;
    std::vector<uint32_t> segment_offsets{0};
    std::vector<uint8_t> closed;     // per curve: 1 when the curve is a closed loop
    std::vector<int32_t> curve_ids;  // per curve: user id (yarn id pass); defaults to the index
    // Per curve: linear RGB in [0, 1] that replaces the body colour of the curve's material
    // (docs/bysdf.md, "Per-yarn colour"). Empty when no curve has one (the usual case), else
    // one per curve. Per curve, not per point: a colour never changes along a yarn.
    std::vector<Vec3> colors;

    size_t curve_count() const { return curve_offsets.size() - 1; }
    size_t point_count() const { return control_points.size(); }
    size_t segment_count() const { return segment_first.size(); }
    bool has_colors() const { return !colors.empty(); }
    uint32_t segment_count(size_t c) const { return segment_offsets[c + 1] - segment_offsets[c]; }

    // Appends one curve given as a chain of B-spline control points. Closed loops get
    // their first three points wrapped to the end.
    void add_curve(const Vec4* points, size_t n, bool is_closed, int32_t id = -1) {
        const uint32_t first = static_cast<uint32_t>(control_points.size());
        control_points.insert(control_points.end(), points, points + n);
        if (is_closed)
            for (size_t i = 0; i < 3 && i < n; ++i) control_points.push_back(points[i]);
        const uint32_t count = static_cast<uint32_t>(control_points.size()) - first;
        for (uint32_t s = 0; s + 3 < count; ++s) segment_first.push_back(first + s);
        finish_curve(is_closed, id);
    }
    // Appends one curve given as independent segments of 4 control points each.
    void add_curve_segments(const Vec4* points, size_t segments, bool is_closed, int32_t id = -1) {
        const uint32_t first = static_cast<uint32_t>(control_points.size());
        control_points.insert(control_points.end(), points, points + 4 * segments);
        for (uint32_t s = 0; s < segments; ++s) segment_first.push_back(first + 4 * s);
        finish_curve(is_closed, id);
    }

    // Appends one converted curve: a chain stays a chain, segments stay segments. A closed
    // chain ends with its first three points again; a closed curve of segments that happens to
    // look like a chain (one Bezier segment: 4 points at 0) does not, and stays segments.
    void add(const BSplineSegments& converted, bool is_closed, int32_t id = -1) {
        if (converted.is_chain() && (!is_closed || wraps_around(converted.points))) {
            // add_curve wraps closed loops itself, so hand it the points before wrapping.
            const size_t n = converted.points.size() - (is_closed ? 3 : 0);
            add_curve(converted.points.data(), n, is_closed, id);
        } else {
            add_curve_segments(converted.points.data(), converted.segment_count(), is_closed, id);
        }
    }

private:
    static bool wraps_around(const std::vector<Vec4>& points) {
        const size_t n = points.size();
        return n >= 6 && std::memcmp(&points[n - 3], &points[0], 3 * sizeof(Vec4)) == 0;
    }
    void finish_curve(bool is_closed, int32_t id) {
        curve_offsets.push_back(static_cast<uint32_t>(control_points.size()));
        segment_offsets.push_back(static_cast<uint32_t>(segment_first.size()));
        closed.push_back(is_closed ? 1 : 0);
        curve_ids.push_back(id >= 0 ? id : static_cast<int32_t>(curve_ids.size()));
    }
};

// Checks what the renderer relies on: finite positions, radius > 0, at least one segment
// per curve, segments inside their curve's points, no colours or one finite colour in [0, 1]
// per curve. Throws InputError naming `source`.
void validate_curves(const YarnCurves& curves, const std::string& source);
// Throws InputError(source, place, ...) unless every channel is a number in [0, 1].
void check_curve_color(Vec3 color, const std::string& source, const std::string& place);

}  // namespace purl
