// Where a ray leaving a surface starts, so that it does not find that surface again, at any
// scale and any distance from the origin. Every kind of hit (triangles, yarn tubes entered or
// left, explicit ply and fiber curves) describes its point by a SpawnPoint: the computed
// position, the surface normal there, and a bound on how far the position may lie from the
// true surface in each coordinate. The origin is that bound pushed along the normal to the
// side the ray leaves on, then one float further out in each coordinate so that rounding the
// sum cannot undo it (the error-bound offset of pbrt-v4, Pharr et al. 2023 sec. 6.8.6).
// Rays never start inside the error bound, and nothing is offset by more than it.
#pragma once
#include "math/vec.h"

namespace purl {

// Bound on the relative error of n float operations: n u / (1 - n u), u = 2^-24 (Higham).
constexpr float float_gamma(int n) {
    constexpr float u = 5.9604644775390625e-8f;
    return float(n) * u / (1 - float(n) * u);
}

struct SpawnPoint {
    Vec3 position;
    Vec3 normal;      // unit; either side of the surface
    float error = 0;  // bound on the position's error in each coordinate, m
};

// The origin of a ray leaving `p` in direction `w` (on w's side of the surface).
Vec3 spawn_origin(const SpawnPoint& p, Vec3 w);

// The shadow ray toward a light sampled from `from`, `distance` along unit `wi` (infinite for
// distant lights), starting at `origin` (spawn_origin's, or where the ray leaves a yarn).
// `empty`: the light lies behind the origin, within the offset, so nothing can be between:
// not occluded. tmax is never negative.
struct ShadowRay {
    Vec3 origin, direction;
    float tmax = 0;
    bool empty = false;
};
ShadowRay shadow_ray_to_light(Vec3 origin, Vec3 from, Vec3 wi, float distance);

// Error bounds of the hit points, from what they are computed from:
// a point rebuilt from barycentrics on the triangle (a, b, c) (pbrt's gamma(7) sum |b_i p_i|,
// with the largest vertex coordinate for every |p_i|), plus what Embree's own triangle test
// may be off by for a ray starting that close (its edges and normal in float, relative to
// the ray origin);
float triangle_point_error(Vec3 a, Vec3 b, Vec3 c);
// a point put at its radius from a cubic curve's centre-line (round curve segment with these
// four control points and radii): the float error of evaluating the centre-line and the
// offset, and of Embree's evaluation of the same sweep surface (it converts the segment to
// Bezier form and subtracts a reference point first).
float curve_point_error(const Vec4* control_points);

// The largest |coordinate| of a point: what float error scales with.
inline float max_abs_coordinate(Vec3 p) { return std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z))); }

}  // namespace purl
