#include "yarn/yarn_tube.h"

#include <algorithm>
#include <cmath>

#include "math/ray_cylinder.h"

namespace purl {
namespace {

// Newton on f(s) = (C(s) - x).T(s), f'(s) = 1 + (C - x).dT/ds, in arc length; returns the
// centre-line point without its frame.
struct Projected {
    uint32_t segment;
    float t;
    CurvePoint c;
    bool converged;
};

// From (segment, t), whose centre-line point c the caller already has; stops when a step is
// below `tolerance_radii` tube radii.
template <class Curve>
Projected project_from(Curve& curve, Vec3 x, uint32_t segment, float t, CurvePoint c, int max_steps,
                       float tolerance_radii = 1e-5f) {
    const CurveFrames& frames = curve.frames();
    const float tolerance = tolerance_radii * std::max(c.radius, 1e-30f);
    bool converged = false;
    for (int step = 0; step < max_steps; ++step) {
        const Vec3 w = c.position - x;
        const float f = dot(w, c.tangent);
        // Beyond the centre of curvature the distance has no minimum here: take a plain step.
        const float fp = std::max(1.0f + dot(w, c.curvature), 0.2f);
        const float ds = clamp(-f / fp, -4 * c.radius, 4 * c.radius);
        if (std::fabs(ds) < tolerance) {  // within tolerance of the closest point: keep this one
            converged = true;
            break;
        }
        if (!frames.advance(segment, t, ds / std::max(c.speed, 1e-30f))) {
            c = curve.evaluate_centreline(segment, t);
            break;  // the closest point is past an open end
        }
        c = curve.evaluate_centreline(segment, t);
    }
    return {segment, t, c, converged};
}

template <class Curve>
Projected project(Curve& curve, Vec3 x, uint32_t segment, float t, int max_steps) {
    return project_from(curve, x, segment, t, curve.evaluate_centreline(segment, t), max_steps);
}

// Signed distance of x outside the tube (negative inside); `at` moves from the previous
// projection (whose centre-line point is reused) to near x's. The distance to the centre-line
// is stationary at the closest point, so a parameter e R off changes it by about e^2 R / 2:
// projecting to 3e-4 R leaves it within 1e-7 R, far inside the exit search's 1e-5 R, for one
// Newton step less per call (settled_exit makes the answer's parameter tight again).
template <class Curve>
float outside_distance(Curve& frames, Vec3 x, Projected& at) {
    at = project_from(frames, x, at.segment, at.t, at.c, 6, 3e-4f);
    return length(x - at.c.position) - at.c.radius;
}

// The exit `distance` along the ray, its centre-line parameter projected to the tight tolerance
// from `at` (the search's last projection, near it).
template <class Curve>
TubeExit settled_exit(Curve& frames, Vec3 point, Vec3 direction, float distance, const Projected& at) {
    const Projected p = project_from(frames, point + direction * distance, at.segment, at.t, at.c, 6);
    return {distance, p.segment, p.t};
}

// Where the ray from `point` leaves the straight cylinder along c's tangent (-1: it does not).
float cylinder_exit(const CurvePoint& c, Vec3 point, Vec3 direction) {
    const RayCylinder r = ray_cylinder(point, direction, c.position, c.tangent, c.radius);
    if (r.along_axis() || r.discriminant() < 0) return -1;
    return r.exit();
}

// Regula falsi (Illinois) inside the bracket h(lo) <= 0 < h(hi).
template <class Curve>
TubeExit illinois(Curve& frames, Vec3 point, Vec3 direction, float radius, float lo, float hi,
                  float h_lo, float h_hi, Projected at) {
    float h = 0;
    int side = 0;
    float x = hi;
    for (int step = 0; step < 40; ++step) {
        x = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);
        if (!(x > lo && x < hi)) x = 0.5f * (lo + hi);
        h = outside_distance(frames, point + direction * x, at);
        if (std::fabs(h) < 1e-5f * radius || hi - lo < 1e-6f * radius) break;
        if (h > 0) {
            hi = x;
            h_hi = h;
            if (side == 1) h_lo *= 0.5f;
            side = 1;
        } else {
            lo = x;
            h_lo = h;
            if (side == -1) h_hi *= 0.5f;
            side = -1;
        }
    }
    return settled_exit(frames, point, direction, std::isfinite(x) ? std::max(x, 0.0f) : 0.0f, at);
}

}  // namespace

CentrelineProjection project_to_centreline(const CurveFrames& frames, Vec3 x, uint32_t segment, float t,
                                           int max_steps) {
    // The segment the projection ends in is expanded once for its steps and the final frame.
    const CachedCurve cache(frames);
    CentrelineProjection r = project_to_centreline_unframed(cache, x, segment, t, max_steps);
    r.point = cache.evaluate(r.segment, r.t);  // the same centre-line point, with its frame
    return r;
}

CentrelineProjection project_to_centreline_unframed(const CachedCurve& frames, Vec3 x, uint32_t segment, float t,
                                                    int max_steps) {
    const Projected p = project(frames, x, segment, t, max_steps);
    CentrelineProjection r;
    r.segment = p.segment;
    r.t = p.t;
    r.point = p.c;
    r.distance = length(x - r.point.position);
    r.converged = p.converged;
    return r;
}

namespace {

template <class Curve>
TubeExit exit_from(Curve& frames, const Projected& start, Vec3 point, Vec3 direction) {
    const CurvePoint& c = start.c;
    const float radius = std::max(c.radius, 1e-30f);

    // Exit from the straight cylinder at the start point: the first guess.
    const RayCylinder straight = ray_cylinder(point, direction, c.position, c.tangent, radius);
    const float max_chord = 200 * radius;
    float guess = clamp(straight.along_axis() ? max_chord : straight.chord(), 0.0f, max_chord);

    // Bracket the first exit: h(lo) <= 0 < h(hi). Inside, R - distance bounds the step.
    Projected at = start;
    float lo = 0, hi = -1, h_lo = -radius, h_hi = 0;
    float h = outside_distance(frames, point + direction * guess, at);
    if (std::fabs(h) < 1e-5f * radius) return settled_exit(frames, point, direction, guess, at);
    // On a bend the cylinder at the guess's own cross-section fits the tube where the ray
    // leaves much better than the one at the start: one such step usually lands within
    // tolerance. Accepted only when it moves less than a radius and keeps the bracket's order.
    {
        const float better = cylinder_exit(at.c, point, direction);
        if (better > 0 && std::fabs(better - guess) < radius && better < max_chord) {
            Projected at2 = at;
            const float h2 = outside_distance(frames, point + direction * better, at2);
            if (std::fabs(h2) < 1e-5f * radius) return settled_exit(frames, point, direction, better, at2);
            // Keep whichever of the two points brackets the exit more tightly.
            if ((h > 0 && h2 > 0 && better < guess) || (h <= 0 && h2 <= 0 && better > guess)) {
                guess = better, h = h2, at = at2;
            } else if (h > 0 && h2 <= 0 && better < guess) {
                // Bracket [better, guess] directly.
                float lo = better, hi = guess, h_lo = h2, h_hi = h;
                return illinois(frames, point, direction, radius, lo, hi, h_lo, h_hi, at);
            } else if (h <= 0 && h2 > 0 && better > guess) {
                float lo = guess, hi = better, h_lo = h, h_hi = h2;
                return illinois(frames, point, direction, radius, lo, hi, h_lo, h_hi, at2);
            }
        }
    }
    if (h > 0) {
        hi = guess;
        h_hi = h;
    } else {
        lo = guess;
        h_lo = h;
        float x = guess;
        for (int step = 0; step < 400 && x < max_chord; ++step) {
            x += std::max(-h, 0.02f * radius);
            h = outside_distance(frames, point + direction * x, at);
            if (h > 0) {
                hi = x;
                h_hi = h;
                break;
            }
            lo = x;
            h_lo = h;
        }
        if (hi < 0) return settled_exit(frames, point, direction, std::min(x, max_chord), at);  // runs along the yarn
    }
    return illinois(frames, point, direction, radius, lo, hi, h_lo, h_hi, at);
}

}  // namespace

float tube_chord_length(const CurveFrames& frames, uint32_t segment, float t, Vec3 point, Vec3 direction) {
    return tube_exit(frames, segment, t, point, direction).distance;
}

TubeExit tube_exit(const CurveFrames& frames, uint32_t segment, float t, Vec3 point, Vec3 direction) {
    CachedCentreline curve(frames);
    return exit_from(curve, project(curve, point, segment, t, 6), point, direction);
}

namespace {

template <class Curve>
TubeExit exit_from_projection(Curve& curve, const CentrelineProjection& start, Vec3 point, Vec3 direction) {
    // A converged projection of `point` is where the projection below would stop at once.
    const Projected p = start.converged ? Projected{start.segment, start.t, start.point, true}
                                        : project(curve, point, start.segment, start.t, 6);
    return exit_from(curve, p, point, direction);
}

}  // namespace

TubeExit tube_exit(const CurveFrames& frames, const CentrelineProjection& start, Vec3 point, Vec3 direction) {
    CachedCentreline curve(frames);
    return exit_from_projection(curve, start, point, direction);
}

TubeExit tube_exit(const CachedCurve& frames, const CentrelineProjection& start, Vec3 point, Vec3 direction) {
    return exit_from_projection(frames, start, point, direction);
}

}  // namespace purl
