// A line against an infinite round cylinder: the one place the yarn tube, the ply search and
// the multi-scale footprint intersect a ray with a straight tube.
#pragma once
#include <algorithm>

#include "math/vec.h"

namespace purl {

// The line origin + t direction against the cylinder of `radius` around the line through
// `point` along unit `axis`: |w + t d| = radius across the axis (w = origin - point, both
// without their part along it), i.e. a t^2 + 2 b t + c = 0.
struct RayCylinder {
    float a;  // |d across|^2: 0 for a line along the axis
    float b;  // w.d across the axis
    float c;  // |w across|^2 - radius^2: negative when the origin is inside

    // The line (nearly) parallel to the axis: no crossing to speak of.
    bool along_axis() const { return !(a > 1e-12f); }
    float discriminant() const { return b * b - a * c; }
    // Where the line enters and leaves (the closest approach when it misses: the square root
    // of a negative discriminant is taken as 0).
    float entry() const { return (-b - safe_sqrt(discriminant())) / a; }
    float exit() const { return (-b + safe_sqrt(discriminant())) / a; }
    // From an origin inside (taken as on the wall when rounding puts it just outside): the
    // distance to the wall, the chord the ray travels inside.
    float chord() const { return (-b + safe_sqrt(b * b - a * std::min(c, 0.0f))) / a; }
};

inline RayCylinder ray_cylinder(Vec3 origin, Vec3 direction, Vec3 point, Vec3 axis, float radius) {
    const Vec3 w = origin - point;
    const Vec3 w_perp = w - axis * dot(w, axis);
    const Vec3 d_perp = direction - axis * dot(direction, axis);
    return {dot(d_perp, d_perp), dot(w_perp, d_perp), dot(w_perp, w_perp) - radius * radius};
}

}  // namespace purl
