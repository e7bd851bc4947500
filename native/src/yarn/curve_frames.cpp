#include "yarn/curve_frames.h"

#include <cmath>

#include "math/bspline.h"
#include "math/frame.h"

namespace purl {
namespace {

constexpr int kTransportSteps = 8;  // double-reflection steps per segment at build time

struct SegmentGeometry {
    Vec3 position, d1, d2;
    float radius;
};

SegmentGeometry segment_geometry(const Vec4* cp, float t) {
    const BSplineWeights b = bspline_basis(t), db = bspline_basis_derivative(t),
                         ddb = bspline_basis_second_derivative(t);
    SegmentGeometry g;
    g.position = g.d1 = g.d2 = Vec3(0.0f);
    g.radius = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3 p = cp[i].xyz();
        g.position += p * b.w[i];
        g.d1 += p * db.w[i];
        g.d2 += p * ddb.w[i];
        g.radius += cp[i].w * b.w[i];
    }
    return g;
}

// Unit direction of d, or of the segment's chord when d vanishes (repeated control points).
Vec3 safe_direction(Vec3 d, const Vec4* cp) {
    float len = length(d);
    if (len > 1e-20f) return d / len;
    d = cp[3].xyz() + cp[2].xyz() - cp[1].xyz() - cp[0].xyz();
    len = length(d);
    return len > 1e-20f ? d / len : Vec3(0, 0, 1);
}

Vec3 start_tangent(const Vec4* cp) { return safe_direction((cp[2].xyz() - cp[0].xyz()) * 0.5f, cp); }
Vec3 end_tangent(const Vec4* cp) { return safe_direction((cp[3].xyz() - cp[1].xyz()) * 0.5f, cp); }

// The smallest rotation taking unit vector a to unit vector b, applied to v.
Vec3 rotate_minimal(Vec3 v, Vec3 a, Vec3 b) {
    const float c = dot(a, b);
    if (c < -0.9999f) return v - b * dot(v, b);  // half-turn: any axis will do, project instead
    const Vec3 k = cross(a, b);
    return v * c + cross(k, v) + k * (dot(k, v) / (1.0f + c));
}

Vec3 rotate_about(Vec3 v, Vec3 axis, float angle) {
    const float c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0f - c));
}

// Double reflection (Wang et al. 2008, algorithm 1): carries r from (x0, t0) to (x1, t1).
Vec3 double_reflection(Vec3 r, Vec3 x0, Vec3 t0, Vec3 x1, Vec3 t1) {
    const Vec3 v1 = x1 - x0;
    const float c1 = dot(v1, v1);
    if (c1 < 1e-30f) return rotate_minimal(r, t0, t1);
    const Vec3 r_left = r - v1 * (2.0f / c1 * dot(v1, r));
    const Vec3 t_left = t0 - v1 * (2.0f / c1 * dot(v1, t0));
    const Vec3 v2 = t1 - t_left;
    const float c2 = dot(v2, v2);
    if (c2 < 1e-30f) return r_left;
    return r_left - v2 * (2.0f / c2 * dot(v2, r_left));
}

Vec3 orthonormalize(Vec3 n, Vec3 t) {
    n -= t * dot(n, t);
    const float len = length(n);
    if (len > 1e-12f) return n / len;
    Vec3 s, u;
    orthonormal_basis(t, s, u);
    return s;
}

// Arc length of the segment between t0 and t1 (3-point Gauss-Legendre).
float segment_length(const Vec4* cp, float t0, float t1) {
    constexpr float x[3] = {-0.7745966692f, 0.0f, 0.7745966692f};
    constexpr float w[3] = {5.0f / 9, 8.0f / 9, 5.0f / 9};
    const float half = 0.5f * (t1 - t0), mid = 0.5f * (t0 + t1);
    float sum = 0;
    for (int i = 0; i < 3; ++i) {
        const BSplineWeights db = bspline_basis_derivative(mid + half * x[i]);
        Vec3 d(0.0f);
        for (int k = 0; k < 4; ++k) d += cp[k].xyz() * db.w[k];
        sum += w[i] * length(d);
    }
    return sum * half;
}

// The uniform cubic B-spline segment in the power basis (its Taylor expansion at t = 0), so
// position and derivatives at any t are a few multiply-adds.
void expand_polynomials(const Vec4* cp, SegmentExpansion& e) {
    e.points = cp;
    const Vec3 p0 = cp[0].xyz(), p1 = cp[1].xyz(), p2 = cp[2].xyz(), p3 = cp[3].xyz();
    e.c0 = (p0 + p1 * 4.0f + p2) * (1.0f / 6);
    e.c1 = (p2 - p0) * 0.5f;
    e.c2 = (p0 - p1 * 2.0f + p2) * 0.5f;
    e.c3 = (p3 - p0 + (p1 - p2) * 3.0f) * (1.0f / 6);
    e.r0 = (cp[0].w + 4 * cp[1].w + cp[2].w) * (1.0f / 6);
    e.r1 = (cp[2].w - cp[0].w) * 0.5f;
    e.r2 = (cp[0].w - 2 * cp[1].w + cp[2].w) * 0.5f;
    e.r3 = (cp[3].w - cp[0].w + 3 * (cp[1].w - cp[2].w)) * (1.0f / 6);
}

}  // namespace

CurveFrames::CurveFrames(const CurveView& curve) : view_(curve) {
    const uint32_t segments = curve.segment_count;
    if (segments == 0 || curve.points == nullptr) {
        view_.segment_count = 0;
        return;
    }
    // Root normal toward the centroid of the segment ends: it turns with the yarn (and does
    // not depend on whether the segments share their control points).
    Vec3 centroid(0.0f), lo(1e30f), hi(-1e30f);
    double radius_sum = 0;
    for (uint32_t k = 0; k <= segments; ++k) {
        const SegmentGeometry g = k < segments ? segment_geometry(curve.segment_points(k), 0)
                                               : segment_geometry(curve.segment_points(segments - 1), 1);
        centroid += g.position;
        lo = min(lo, g.position);
        hi = max(hi, g.position);
        radius_sum += g.radius;
    }
    centroid = centroid / static_cast<float>(segments + 1);
    reference_radius_ = static_cast<float>(radius_sum / (segments + 1));
    const Vec4* first = curve.segment_points(0);
    const Vec3 root = segment_geometry(first, 0).position, root_tangent = start_tangent(first);
    Vec3 r = centroid - root;
    r -= root_tangent * dot(r, root_tangent);
    // A straight yarn has no shape to follow: fall back to a world-aligned basis.
    r = length(r) > 1e-3f * max_component(hi - lo) ? normalize(r) : Frame::from_normal(root_tangent).s;

    knots_.resize(segments + 1);
    float s = 0;
    Vec3 previous_end_tangent = root_tangent;
    for (uint32_t k = 0; k < segments; ++k) {
        const Vec4* cp = curve.segment_points(k);
        // Separate segments may meet at an angle: turn minimally onto this segment's start.
        r = orthonormalize(rotate_minimal(r, previous_end_tangent, start_tangent(cp)), start_tangent(cp));
        knots_[k] = Vec4(r, s);
        SegmentGeometry a = segment_geometry(cp, 0);
        Vec3 ta = start_tangent(cp);
        for (int step = 1; step <= kTransportSteps; ++step) {
            const float t0 = float(step - 1) / kTransportSteps, t1 = float(step) / kTransportSteps;
            const SegmentGeometry b = segment_geometry(cp, t1);
            const Vec3 tb = step == kTransportSteps ? end_tangent(cp) : safe_direction(b.d1, cp);
            r = double_reflection(r, a.position, ta, b.position, tb);
            s += segment_length(cp, t0, t1);
            a = b;
            ta = tb;
        }
        r = orthonormalize(r, ta);
        previous_end_tangent = ta;
    }
    knots_[segments] = Vec4(r, s);

    if (curve.closed && s > 0) {
        // Spread the loop's holonomy: the end frame must come back onto the root frame.
        const Vec3 t0 = start_tangent(curve.segment_points(0));
        const Vec3 r_end = orthonormalize(rotate_minimal(r, previous_end_tangent, t0), t0);
        const Vec3 r0 = knots_[0].xyz();
        const float holonomy = std::atan2(dot(cross(r_end, r0), t0), dot(r_end, r0));
        for (uint32_t k = 1; k <= segments; ++k) {
            const Vec3 axis = k < segments ? start_tangent(curve.segment_points(k))
                                           : end_tangent(curve.segment_points(segments - 1));
            const Vec3 n = rotate_about(knots_[k].xyz(), axis, holonomy * knots_[k].w / s);
            knots_[k] = Vec4(orthonormalize(n, axis), knots_[k].w);
        }
    }

    // Per segment, the turn about the start tangent that takes the start normal to the end
    // normal carried back along the segment: evaluate() spreads it linearly.
    twist_.resize(segments);
    for (uint32_t k = 0; k < segments; ++k) {
        const Vec4* cp = curve.segment_points(k);
        const Vec3 ta = start_tangent(cp);
        const Vec3 na = orthonormalize(knots_[k].xyz(), ta);
        const Vec3 back = orthonormalize(rotate_minimal(knots_[k + 1].xyz(), end_tangent(cp), ta), ta);
        twist_[k] = std::atan2(dot(cross(na, back), ta), dot(na, back));
    }
}

SegmentExpansion CurveFrames::expand(uint32_t segment) const {
    const Vec4* cp = view_.segment_points(segment);
    SegmentExpansion e;
    expand_polynomials(cp, e);
    if (knots_.empty()) return e;  // centre-line only (an empty object has no frames)
    const Vec3 end = (cp[3].xyz() - cp[1].xyz()) * 0.5f;
    e.start_speed = length(e.c1);
    e.end_speed = length(end);
    e.start_tangent = e.start_speed > 1e-20f ? e.c1 / e.start_speed : start_tangent(cp);
    e.start_normal = knots_[segment].xyz();
    e.start_side = cross(e.start_tangent, e.start_normal);
    e.twist = twist_[segment];
    e.start_length = knots_[segment].w;
    e.end_length = knots_[segment + 1].w;
    return e;
}

CurvePoint SegmentExpansion::evaluate_centreline(float t) const {
    CurvePoint c;
    c.position = c0 + (c1 + (c2 + c3 * t) * t) * t;
    const Vec3 d1 = c1 + (c2 * 2.0f + c3 * (3 * t)) * t, d2 = c2 * 2.0f + c3 * (6 * t);
    c.radius = r0 + (r1 + (r2 + r3 * t) * t) * t;
    c.speed = length(d1);
    c.tangent = c.speed > 1e-20f ? d1 / c.speed : safe_direction(d1, points);
    const float inv_speed = c.speed > 1e-20f ? 1.0f / c.speed : 0.0f;
    c.curvature = (d2 - c.tangent * dot(d2, c.tangent)) * (inv_speed * inv_speed);
    c.arc_length = 0;
    return c;
}

SegmentExpansion CurveFrames::expand_centreline(uint32_t segment) const {
    SegmentExpansion e;
    expand_polynomials(view_.segment_points(segment), e);
    return e;
}

CurvePoint CurveFrames::evaluate_centreline(uint32_t segment, float t) const {
    // Only the polynomial part of the expansion (cheap); no frame constants.
    return expand_centreline(segment).evaluate_centreline(t);
}

CurvePoint SegmentExpansion::evaluate(float t) const {
    CurvePoint c = evaluate_centreline(t);

    // The start normal, turned about the start tangent by the segment's share of twist, then
    // carried onto this tangent by the smallest rotation (exactly the end normal at t = 1).
    const float turn = twist * clamp(t, 0.0f, 1.0f);
    float cos_turn, sin_turn;
    if (std::fabs(turn) < 0.25f) {  // series to x^5: error below 1e-7 here
        const float x2 = turn * turn;
        cos_turn = 1 - x2 * (0.5f - x2 * (1.0f / 24));
        sin_turn = turn * (1 - x2 * (1.0f / 6 - x2 * (1.0f / 120)));
    } else {
        cos_turn = std::cos(turn);
        sin_turn = std::sin(turn);
    }
    const Vec3 na = start_normal * cos_turn + start_side * sin_turn;
    // na is unit and perpendicular to the start tangent (the knots are orthonormalized at build
    // time), and the smallest rotation keeps both: only the half-turn branch needs orthonormalizing.
    const Vec3& ta = start_tangent;
    const float ct = dot(ta, c.tangent);
    float swing = 0;  // the smallest rotation's own turn about the tangent, rad/m (half-turns: 0)
    if (ct > -0.9f) {
        const Vec3 k = cross(ta, c.tangent);
        c.normal = na * ct + cross(k, na) + k * (dot(k, na) / (1.0f + ct));
        swing = dot(c.curvature, k) / (1.0f + ct);
    } else {
        c.normal = orthonormalize(rotate_minimal(na, ta, c.tangent), c.tangent);
    }
    c.binormal = cross(c.tangent, c.normal);
    // The frame's turn about the tangent: the twist share, less the swing (checked against
    // finite differences of the frame in the tests).
    const float speed = std::max(c.speed, 1e-30f);
    c.frame_turn = (t >= 0 && t <= 1 ? twist / speed : 0.0f) - swing;

    // Arc length: cubic Hermite through the boundary lengths and speeds, linear outside.
    if (t < 0) {
        c.arc_length = start_length + t * start_speed;
        c.arc_rate = start_speed / speed;
    } else if (t > 1) {
        c.arc_length = end_length + (t - 1) * end_speed;
        c.arc_rate = end_speed / speed;
    } else {
        const float t2 = t * t, t3 = t2 * t;
        c.arc_rate = ((6 * t2 - 6 * t) * (start_length - end_length) + (3 * t2 - 4 * t + 1) * start_speed +
                      (3 * t2 - 2 * t) * end_speed) / speed;
        c.arc_length = (2 * t3 - 3 * t2 + 1) * start_length + (t3 - 2 * t2 + t) * start_speed +
                       (-2 * t3 + 3 * t2) * end_length + (t3 - t2) * end_speed;
    }
    return c;
}

bool CurveFrames::advance(uint32_t& segment, float& t, float dt) const {
    const uint32_t n = view_.segment_count;
    // A non-finite step (zero speed on a degenerate curve) would never end the walk below.
    if (!std::isfinite(dt) || !std::isfinite(t)) return false;
    if (t + dt >= 0.0f && t + dt <= 1.0f) {
        t += dt;
        return true;
    }
    // Position along the whole curve in segments, in double so huge steps stay exact enough.
    double position = double(segment) + double(t) + double(dt);
    if (view_.closed) {
        position = std::fmod(position, double(n));
        if (position < 0) position += n;
        segment = std::min(static_cast<uint32_t>(position), n - 1);
        t = static_cast<float>(position - segment);
        return true;
    }
    if (position > double(n)) {  // past the end: extrapolate at most half a segment
        segment = n - 1;
        t = static_cast<float>(std::min(position - (n - 1), 1.5));
        return false;
    }
    if (position < 0.0) {
        segment = 0;
        t = static_cast<float>(std::max(position, -0.5));
        return false;
    }
    segment = std::min(static_cast<uint32_t>(position), n - 1);
    t = static_cast<float>(position - segment);
    return true;
}

float CurveFrames::azimuth(const CurvePoint& c, Vec3 x) {
    const Vec3 d = x - c.position;
    const float a = std::atan2(dot(d, c.binormal), dot(d, c.normal));
    return a < 0 ? a + 2 * kPi : a;
}

std::vector<CurveFrames> build_curve_frames(const Vec4* points, const uint32_t* offsets,
                                            const uint8_t* closed, size_t curve_count) {
    std::vector<CurveFrames> frames;
    frames.reserve(curve_count);
    for (size_t c = 0; c < curve_count; ++c)
        frames.emplace_back(CurveView::chain(points + offsets[c], offsets[c + 1] - offsets[c],
                                             closed != nullptr && closed[c] != 0));
    return frames;
}

}  // namespace purl
