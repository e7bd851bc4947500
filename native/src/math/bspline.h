// Uniform cubic B-spline segments: position and derivatives for t in [0, 1].
#pragma once
#include "math/vec.h"

namespace purl {

struct BSplineWeights {
    float w[4];
};

inline BSplineWeights bspline_basis(float t) {
    const float s = 1.0f - t;
    return {{s * s * s / 6.0f, (3 * t * t * t - 6 * t * t + 4) / 6.0f,
             (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0f, t * t * t / 6.0f}};
}
inline BSplineWeights bspline_basis_derivative(float t) {
    const float s = 1.0f - t;
    return {{-0.5f * s * s, 1.5f * t * t - 2 * t, -1.5f * t * t + t + 0.5f, 0.5f * t * t}};
}
inline BSplineWeights bspline_basis_second_derivative(float t) {
    return {{1 - t, 3 * t - 2, -3 * t + 1, t}};
}

template <class P>
inline P bspline_combine(const P* cp, const BSplineWeights& b) {
    return cp[0] * b.w[0] + cp[1] * b.w[1] + cp[2] * b.w[2] + cp[3] * b.w[3];
}
inline Vec3 bspline_point(const Vec3* cp, float t) { return bspline_combine(cp, bspline_basis(t)); }
inline Vec3 bspline_tangent(const Vec3* cp, float t) {
    return bspline_combine(cp, bspline_basis_derivative(t));
}

}  // namespace purl
