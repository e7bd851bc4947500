// Rotation-minimizing frames along one yarn centre-line (a uniform cubic B-spline with a
// radius per control point), by the double-reflection method of Wang, Juettler, Zheng and
// Liu 2008. Frames are computed once, stored at segment boundaries (a normal, the arc length
// from the root and the segment's twist: 5 floats per segment) and interpolated at query time, so the
// azimuthal phase u_yarn and the length v_yarn of a hit follow the yarn when it moves or bends.
//
// Closed loops stay continuous across the seam: the frame's holonomy (the twist a
// rotation-minimizing frame accumulates around a loop) is spread evenly along the loop.
// The root normal comes from the curve's own shape (toward its centroid), so rotating or
// moving a yarn rotates or moves its frames with it; a straight yarn falls back to a world basis.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "math/vec.h"

namespace purl {

// Non-owning view of one curve's control points, (x, y, z, radius) in metres. Either a chain
// (segment i uses points i .. i+3; a closed loop of n points is stored as n + 3 points with
// its first three repeated) or separate segments (segment i uses points first[i] .. first[i]+3).
struct CurveView {
    const Vec4* points = nullptr;
    uint32_t point_count = 0;
    const uint32_t* segment_first = nullptr;  // null for a chain
    uint32_t segment_count = 0;
    bool closed = false;

    static CurveView chain(const Vec4* points, uint32_t count, bool closed) {
        return {points, count, nullptr, count >= 4 ? count - 3 : 0, closed};
    }
    static CurveView separate_segments(const Vec4* points, uint32_t count, const uint32_t* first,
                                       uint32_t segments, bool closed) {
        return {points, count, first, segments, closed};
    }
    const Vec4* segment_points(uint32_t segment) const {
        return points + (segment_first ? segment_first[segment] : segment);
    }
};

// The centre-line and its frame at one curve parameter.
struct CurvePoint {
    Vec3 position;   // m
    Vec3 tangent;    // unit, along increasing t
    Vec3 normal;     // unit reference normal (rotation-minimizing)
    Vec3 binormal;   // tangent x normal
    Vec3 curvature;  // dT/ds, 1/m (perpendicular to the tangent)
    float speed;     // |dC/dt|, m per unit t
    float radius;    // yarn radius R, m
    float arc_length;  // v_yarn: m from the root along the centre-line
    // What a helix around the centre-line needs for its exact derivative, since the frame and
    // v_yarn are interpolated: how fast the frame turns the normal toward the binormal (rad
    // per m; zero for an exact rotation-minimizing frame, small but not zero here), and
    // d arc_length / ds (1 for the exact arc length, within a few 1e-3 of it here).
    // evaluate_centreline leaves them at 0 and 1.
    float frame_turn = 0;
    float arc_rate = 1;
};

// One segment's centre-line as polynomials in t, plus the constants its frame needs (start
// tangent and normal, twist, end speeds, boundary arc lengths): everything evaluate() needs
// that does not depend on t, computed once. CurveFrames::evaluate goes through it, so a caller
// that keeps an expansion (CachedCurve) gets exactly the same numbers without recomputing the
// B-spline basis and the frame constants at every Newton step.
struct SegmentExpansion {
    const Vec4* points = nullptr;  // the segment's 4 control points (zero-speed fallbacks)
    Vec3 c0, c1, c2, c3;           // position = c0 + c1 t + c2 t^2 + c3 t^3
    float r0 = 0, r1 = 0, r2 = 0, r3 = 0;  // radius, the same way
    Vec3 start_tangent, start_normal, start_side;  // at t = 0; side = tangent x normal
    float twist = 0;                 // turn of the normal about start_tangent over the segment, rad
    float start_speed = 0, end_speed = 0;    // |dC/dt| at t = 0 and 1
    float start_length = 0, end_length = 0;  // arc length from the root at t = 0 and 1

    CurvePoint evaluate(float t) const;
    CurvePoint evaluate_centreline(float t) const;
};

class CurveFrames {
public:
    CurveFrames() = default;
    // Precomputes the frames; the view's arrays must outlive this object. A curve without
    // segments gives an empty object (segment_count() == 0) that must not be queried.
    explicit CurveFrames(const CurveView& curve);

    CurvePoint evaluate(uint32_t segment, float t) const { return expand(segment).evaluate(t); }
    // Position, tangent, curvature, speed and radius only (normal, binormal and arc length
    // are left zero): enough to project points onto the centre-line, at a third of the cost.
    CurvePoint evaluate_centreline(uint32_t segment, float t) const;
    SegmentExpansion expand(uint32_t segment) const;
    // The polynomial part of expand() only (no frame constants): what evaluate_centreline uses.
    SegmentExpansion expand_centreline(uint32_t segment) const;
    // Moves (segment, t) by dt across segment boundaries (wrapping on closed loops).
    // Open curves stop at their ends (t may extrapolate at most half a segment past them);
    // returns false when it had to stop.
    bool advance(uint32_t& segment, float& t, float dt) const;

    // Azimuthal phase u_yarn in [0, 2 pi) of point x around the centre-line point c.
    static float azimuth(const CurvePoint& c, Vec3 x);

    uint32_t segment_count() const { return view_.segment_count; }
    bool closed() const { return view_.closed; }
    float total_length() const { return knots_.empty() ? 0.0f : knots_.back().w; }  // m
    // Mean radius at the segment ends: the length unit of twist rates on this curve, m.
    float reference_radius() const { return reference_radius_; }
    const CurveView& view() const { return view_; }
    size_t memory_bytes() const {
        return sizeof(*this) + knots_.capacity() * sizeof(Vec4) + twist_.capacity() * sizeof(float);
    }

private:
    CurveView view_;
    // Per segment boundary k (segment_count + 1 of them): reference normal xyz and arc length.
    std::vector<Vec4> knots_;
    std::vector<float> twist_;  // per segment: turn of the normal about the start tangent, rad
    float reference_radius_ = 0;
};

// A few segment expansions of one curve kept for the length of one query (not shared between
// threads): the stretch of yarn a ray crosses spans a handful of segments, each evaluated many
// times by the ply search. Direct-mapped by segment index; same results as CurveFrames.
// kCentrelineOnly keeps only the polynomials (CurveFrames::expand_centreline): enough for
// projections onto the centre-line, at a third of the cost.
template <bool kCentrelineOnly, uint32_t kSlots>
class SegmentCache {
public:
    explicit SegmentCache(const CurveFrames& frames) : frames_(frames) {
        for (uint32_t& tag : tags_) tag = kEmpty;
    }
    const CurveFrames& frames() const { return frames_; }
    uint32_t segment_count() const { return frames_.segment_count(); }
    bool closed() const { return frames_.closed(); }
    CurvePoint evaluate(uint32_t segment, float t) const {
        static_assert(!kCentrelineOnly, "a centre-line cache has no frames");
        return segment_expansion(segment).evaluate(t);
    }
    CurvePoint evaluate_centreline(uint32_t segment, float t) const {
        return segment_expansion(segment).evaluate_centreline(t);
    }
    const SegmentExpansion& segment_expansion(uint32_t segment) const {
        const uint32_t slot = segment % kSlots;
        if (tags_[slot] != segment) {
            slots_[slot] = kCentrelineOnly ? frames_.expand_centreline(segment) : frames_.expand(segment);
            tags_[slot] = segment;
        }
        return slots_[slot];
    }

private:
    static constexpr uint32_t kEmpty = ~0u;
    const CurveFrames& frames_;
    mutable uint32_t tags_[kSlots];
    // Left uninitialized (a slot is read only after its tag is set): zeroing a kilobyte per
    // query would cost a noticeable share of it.
    union {
        mutable SegmentExpansion slots_[kSlots];
    };
};
// The ply search's cache (frames and all).
using CachedCurve = SegmentCache<false, 8>;
// A tube-exit search's cache: it projects a handful of points along the ray, mostly within one
// or two segments.
using CachedCentreline = SegmentCache<true, 4>;

// Frames for a set of chain curves laid out as YarnCurves stores them (offsets[c] ..
// offsets[c+1] are curve c's points; closed loops already wrapped), without linking purl_scene.
std::vector<CurveFrames> build_curve_frames(const Vec4* points, const uint32_t* offsets,
                                            const uint8_t* closed, size_t curve_count);

}  // namespace purl
