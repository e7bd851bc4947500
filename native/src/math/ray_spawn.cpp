#include "math/ray_spawn.h"

#include <cmath>
#include <limits>

namespace purl {

Vec3 spawn_origin(const SpawnPoint& p, Vec3 w) {
    const Vec3 n = p.normal;
    // The error box's extent along n: how far the true surface may be from the position.
    const float d = p.error * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
    const Vec3 offset = dot(w, n) >= 0 ? n * d : n * -d;
    Vec3 o = p.position + offset;
    // position + offset is rounded to nearest, which may fall back toward the surface.
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0) o[i] = std::nextafter(o[i], kInf);
        else if (offset[i] < 0) o[i] = std::nextafter(o[i], -kInf);
    }
    return o;
}

ShadowRay shadow_ray_to_light(Vec3 origin, Vec3 from, Vec3 wi, float distance) {
    ShadowRay r;
    r.origin = origin;
    if (!std::isfinite(distance)) {  // sun, environment
        r.direction = wi;
        r.tmax = std::numeric_limits<float>::infinity();
        return r;
    }
    const Vec3 to = from + wi * distance;
    const Vec3 d = to - r.origin;
    const float len = length(d);
    // The light is behind the moved origin, or on it: nearer than the surface's own error,
    // so no surface can lie between.
    if (!(dot(d, wi) > 0) || !(len > 0)) {
        r.empty = true;
        return r;
    }
    r.direction = d / len;
    // Short of the light itself: a surface the light touches does not shadow it.
    r.tmax = len * (1 - 1e-4f);
    return r;
}

float triangle_point_error(Vec3 a, Vec3 b, Vec3 c) {
    const float m = std::max(max_abs_coordinate(a), std::max(max_abs_coordinate(b), max_abs_coordinate(c)));
    // gamma(7): b0 p0 + b1 p1 + b2 p2 with b0 = 1 - b1 - b2. Embree's test, relative to a ray
    // origin near the point, sees the plane through v0 - o and a normal from edge cross
    // products: each off by a few units in the last place of the vertices, which gamma(16)
    // bounds with room (measured: Robustness.PlaneLitAtAnyWidthAndDistance).
    return (float_gamma(7) + float_gamma(16)) * m;
}

float curve_point_error(const Vec4* cp) {
    float m = 0, r = 0, extent = 0;
    for (int i = 0; i < 4; ++i) {
        m = std::max(m, max_abs_coordinate(cp[i].xyz()));
        r = std::max(r, cp[i].w);
        extent = std::max(extent, max_abs_coordinate(cp[i].xyz() - cp[0].xyz()));
    }
    // Ours: the centre-line from four weighted points (or its power form), then the radius
    // along a unit vector. Embree's: the same surface after a basis change and a shift to a
    // point near the curve, evaluated with an error of 16 float epsilons times the shifted
    // curve's size (its P_err).
    return float_gamma(16) * (m + r) + float_gamma(32) * (extent + r);
}

}  // namespace purl
