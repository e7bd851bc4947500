// Affine 4x4 transforms, stored row-major like Blender's Matrix rows.
#pragma once
#include <array>
#include <cmath>

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

    // Camera-style placement: local -Z looks at `target`, local +Y is as close to `up` as possible
    // (Transform64::look_at).
    static Transform look_at(Vec3 position, Vec3 target, Vec3 up);
};

using Point64 = std::array<double, 3>;

inline Point64 to_point64(Vec3 p) { return {p.x, p.y, p.z}; }

// A placement as a scene file gives it, in double. A float is 1 mm apart at 1e4 m, two yarn radii,
// so positions are composed here and made relative to the scene's origin (SceneDesc::origin)
// before they become floats.
struct Transform64 {
    double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  // the last row is 0 0 0 1

    Point64 point(const Point64& p) const {
        Point64 out;
        for (int r = 0; r < 3; ++r) out[r] = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
        return out;
    }
    Point64 translation() const { return {m[0][3], m[1][3], m[2][3]}; }
    // Mean scale of the linear part (radii scale with their curves).
    double uniform_scale() const {
        const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        return std::cbrt(std::fabs(det));
    }
    // The same placement seen from `origin`, as floats: linear part rounded, translation - origin.
    Transform relative_to(const Point64& origin) const {
        Transform t;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) t.m[r][c] = float(m[r][c]);
            t.m[r][3] = float(m[r][3] - origin[r]);
        }
        return t;
    }

    // Camera-style placement: local -Z looks at `target`, local +Y is as close to `up` as possible.
    // In double, any two distinct points give a finite frame (their difference may overflow
    // float); an `up` along the view falls back to world Y (then X).
    static Transform64 look_at(const Point64& position, const Point64& target, const Point64& up) {
        auto cross_d = [](const Point64& a, const Point64& b) {
            return Point64{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        };
        auto length_d = [](const Point64& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); };
        auto normalized = [&](Point64 a) {
            const double n = length_d(a);
            for (double& c : a) c /= n;
            return a;
        };
        const Point64 back = normalized({position[0] - target[0], position[1] - target[1],
                                         position[2] - target[2]});  // local +Z
        Point64 right = cross_d(normalized(up), back);
        if (length_d(right) < 1e-6) right = cross_d({0, 1, 0}, back);
        if (length_d(right) < 1e-6) right = cross_d({1, 0, 0}, back);  // looking along Y as well
        right = normalized(right);
        const Point64 true_up = cross_d(back, right);
        Transform64 t;
        for (int r = 0; r < 3; ++r) {
            t.m[r][0] = right[r];
            t.m[r][1] = true_up[r];
            t.m[r][2] = back[r];
            t.m[r][3] = position[r];
        }
        return t;
    }
};

inline Transform Transform::look_at(Vec3 position, Vec3 target, Vec3 up) {
    return Transform64::look_at(to_point64(position), to_point64(target), to_point64(up)).relative_to({0, 0, 0});
}

}  // namespace purl
