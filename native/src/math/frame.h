// Orthonormal frames: a shading model works in local coordinates where n = +z.
#pragma once
#include "math/vec.h"

namespace purl {

// Two unit vectors orthogonal to n (Duff et al. 2017, branchless).
inline void orthonormal_basis(Vec3 n, Vec3& s, Vec3& t) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
}

struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    static Frame from_normal(Vec3 n) {
        Frame f;
        f.n = n;
        orthonormal_basis(n, f.s, f.t);
        return f;
    }
    // Frame with n as normal and s as close to `tangent` as orthogonality allows.
    static Frame from_normal_tangent(Vec3 n, Vec3 tangent) {
        Vec3 s = tangent - n * dot(n, tangent);
        const float len = length(s);
        if (!(len > 1e-6f)) return from_normal(n);
        Frame f;
        f.n = n;
        f.s = s / len;
        f.t = cross(f.n, f.s);
        return f;
    }
    Vec3 to_local(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace purl
