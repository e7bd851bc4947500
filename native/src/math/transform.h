// Affine 4x4 transforms, stored row-major like Blender's Matrix rows.
#pragma once
#include "math/vec.h"

namespace purl {

struct Transform {
    float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    Vec3 point(Vec3 p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(Vec3 v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
    Vec3 translation() const { return column(3); }
    // Mean scale of the linear part, used to scale radii with their curves.
    float uniform_scale() const {
        return std::cbrt(std::fabs(dot(column(0), cross(column(1), column(2)))));
    }

    // Camera-style placement: local -Z looks at `target`, local +Y is as close to `up` as possible.
    static Transform look_at(Vec3 position, Vec3 target, Vec3 up) {
        const Vec3 back = normalize(position - target);  // local +Z
        Vec3 right = cross(up, back);
        if (length(right) < 1e-6f) right = cross(Vec3(0, 1, 0), back);
        right = normalize(right);
        const Vec3 true_up = cross(back, right);
        Transform t;
        for (int r = 0; r < 3; ++r) {
            t.m[r][0] = right[r];
            t.m[r][1] = true_up[r];
            t.m[r][2] = back[r];
            t.m[r][3] = position[r];
        }
        return t;
    }
};

}  // namespace purl
