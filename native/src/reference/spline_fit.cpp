#include "reference/spline_fit.h"

#include <cassert>

namespace purl {
namespace {

// Solves the tridiagonal system sub[i] x[i-1] + diag[i] x[i] + super[i] x[i+1] = rhs[i] (Thomas;
// the systems here are strictly diagonally dominant, so no pivoting is needed). In place in rhs.
void solve_tridiagonal(const std::vector<double>& sub, const std::vector<double>& diag,
                       const std::vector<double>& super, std::vector<Point4d>& rhs) {
    const size_t n = diag.size();
    std::vector<double> c(n);
    double denom = diag[0];
    c[0] = super[0] / denom;
    for (int k = 0; k < 4; ++k) rhs[0].v[k] /= denom;
    for (size_t i = 1; i < n; ++i) {
        denom = diag[i] - sub[i] * c[i - 1];
        c[i] = super[i] / denom;
        for (int k = 0; k < 4; ++k) rhs[i].v[k] = (rhs[i].v[k] - sub[i] * rhs[i - 1].v[k]) / denom;
    }
    for (size_t i = n - 1; i-- > 0;)
        for (int k = 0; k < 4; ++k) rhs[i].v[k] -= c[i] * rhs[i + 1].v[k];
}

Vec4 to_float(const Point4d& p) {
    return Vec4(float(p.v[0]), float(p.v[1]), float(p.v[2]), float(p.v[3]));
}

}  // namespace

std::vector<Vec4> interpolate_closed(const std::vector<Point4d>& samples) {
    const size_t n = samples.size();
    assert(n >= 3);
    // X_j, the point whose basis function peaks at knot j: (X_{j-1} + 4 X_j + X_{j+1}) / 6 = S_j
    // cyclically. Sherman-Morrison: the corners move onto the diagonal (gamma = -4), then one
    // correction along u = (gamma, 0, ..., 0, 1).
    const double gamma = -4;
    std::vector<double> sub(n, 1.0), diag(n, 4.0), super(n, 1.0);
    diag[0] = 4 - gamma;
    diag[n - 1] = 4 - 1.0 / gamma;
    std::vector<Point4d> x(n), z(n);
    for (size_t j = 0; j < n; ++j)
        for (int k = 0; k < 4; ++k) x[j].v[k] = 6 * samples[j].v[k];
    z[0].v[0] = gamma;
    z[n - 1].v[0] = 1;
    solve_tridiagonal(sub, diag, super, x);
    solve_tridiagonal(sub, diag, super, z);
    const double z0 = z[0].v[0], zn = z[n - 1].v[0];
    double fact[4];
    for (int k = 0; k < 4; ++k) fact[k] = (x[0].v[k] + x[n - 1].v[k] / gamma) / (1 + z0 + zn / gamma);
    for (size_t j = 0; j < n; ++j)
        for (int k = 0; k < 4; ++k) x[j].v[k] -= fact[k] * z[j].v[0];
    // Control point j is X_{j-1}: segment j then starts at (X_{j-1} + 4 X_j + X_{j+1}) / 6 = S_j.
    std::vector<Vec4> out(n);
    for (size_t j = 0; j < n; ++j) out[j] = to_float(x[(j + n - 1) % n]);
    return out;
}

Point4d end_slope(const Point4d& p0, const Point4d& p_half, const Point4d& p1, const Point4d& p_3half,
                  const Point4d& p2) {
    // f'(0) = (-25 f0 + 48 f1 - 36 f2 + 16 f3 - 3 f4) / (12 delta) at spacing delta = 1/2 knot.
    Point4d d;
    for (int k = 0; k < 4; ++k)
        d.v[k] = (-25 * p0.v[k] + 48 * p_half.v[k] - 36 * p1.v[k] + 16 * p_3half.v[k] - 3 * p2.v[k]) / 6;
    return d;
}

std::vector<Vec4> interpolate_open(const std::vector<Point4d>& s, const Point4d* start_slope,
                                   const Point4d* end_slope) {
    const size_t n = s.size();
    assert(n >= 4);
    // Slopes per knot step at both ends; by default from the cubic through the four end samples.
    Point4d d0, d1;
    for (int k = 0; k < 4; ++k) {
        d0.v[k] = (-11 * s[0].v[k] + 18 * s[1].v[k] - 9 * s[2].v[k] + 2 * s[3].v[k]) / 6;
        d1.v[k] = (11 * s[n - 1].v[k] - 18 * s[n - 2].v[k] + 9 * s[n - 3].v[k] - 2 * s[n - 4].v[k]) / 6;
    }
    if (start_slope) d0 = *start_slope;
    if (end_slope) d1 = *end_slope;
    // Unknowns X_0 .. X_{n-1} (control points 1 .. n); the outer control points follow from
    // the slopes, (X_1 - Q_0) / 2 = d0 and (Q_{n+1} - X_{n-2}) / 2 = d1.
    std::vector<double> sub(n, 1.0), diag(n, 4.0), super(n, 1.0);
    super[0] = 2;
    sub[n - 1] = 2;
    std::vector<Point4d> x(n);
    for (size_t j = 0; j < n; ++j)
        for (int k = 0; k < 4; ++k) x[j].v[k] = 6 * s[j].v[k];
    for (int k = 0; k < 4; ++k) {
        x[0].v[k] += 2 * d0.v[k];
        x[n - 1].v[k] -= 2 * d1.v[k];
    }
    solve_tridiagonal(sub, diag, super, x);
    std::vector<Vec4> out(n + 2);
    Point4d first, last;
    for (int k = 0; k < 4; ++k) {
        first.v[k] = x[1].v[k] - 2 * d0.v[k];
        last.v[k] = x[n - 2].v[k] + 2 * d1.v[k];
    }
    out[0] = to_float(first);
    for (size_t j = 0; j < n; ++j) out[j + 1] = to_float(x[j]);
    out[n + 1] = to_float(last);
    return out;
}

}  // namespace purl
