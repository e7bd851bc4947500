#include "math/spline_convert.h"

#include <stdexcept>
#include <string>

namespace purl {
namespace {

// Vec4 arithmetic in double so the 7/6 and 11/6 weights do not lose precision.
struct D4 {
    double x = 0, y = 0, z = 0, w = 0;
};
D4 to_d(const Vec4& v) { return {v.x, v.y, v.z, v.w}; }
Vec4 to_f(const D4& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z),
            static_cast<float>(v.w)};
}
D4 operator+(D4 a, D4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
D4 operator-(D4 a, D4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
D4 operator*(double s, D4 a) { return {s * a.x, s * a.y, s * a.z, s * a.w}; }

// out = M * in for a 4x4 basis-change matrix M (rows = output points).
void apply(const double m[4][4], const Vec4 in[4], Vec4 out[4]) {
    const D4 p[4] = {to_d(in[0]), to_d(in[1]), to_d(in[2]), to_d(in[3])};
    for (int r = 0; r < 4; ++r)
        out[r] = to_f(m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3] * p[3]);
}

// M_bspline^-1 * M_catmullrom: Catmull-Rom segment (p0..p3) as B-spline control points.
constexpr double kCatmullRomToBSpline[4][4] = {{7 / 6.0, -4 / 6.0, 5 / 6.0, -2 / 6.0},
                                               {-2 / 6.0, 11 / 6.0, -4 / 6.0, 1 / 6.0},
                                               {1 / 6.0, -4 / 6.0, 11 / 6.0, -2 / 6.0},
                                               {-2 / 6.0, 5 / 6.0, -4 / 6.0, 7 / 6.0}};
// M_bspline^-1 * M_bezier.
constexpr double kBezierToBSpline[4][4] = {
    {6, -7, 2, 0}, {0, 2, -1, 0}, {0, -1, 2, 0}, {0, 2, -7, 6}};
// M_bezier^-1 * M_bspline.
constexpr double kBSplineToBezier[4][4] = {{1 / 6.0, 4 / 6.0, 1 / 6.0, 0},
                                           {0, 4 / 6.0, 2 / 6.0, 0},
                                           {0, 2 / 6.0, 4 / 6.0, 0},
                                           {0, 1 / 6.0, 4 / 6.0, 1 / 6.0}};

// Independent segment: 4 points of its own, shared with no neighbour.
void append_segment(BSplineSegments& out, const Vec4 cp[4]) {
    out.segment_first.push_back(static_cast<uint32_t>(out.points.size()));
    out.points.insert(out.points.end(), cp, cp + 4);
}

// Chain of control points (wrapped when closed) with segment s at point s.
BSplineSegments make_chain(std::vector<Vec4> cps, bool closed) {
    BSplineSegments out;
    const size_t n = cps.size();
    if (closed)
        for (size_t i = 0; i < 3; ++i) cps.push_back(cps[i % n]);
    out.points = std::move(cps);
    const size_t segments = out.points.size() - 3;
    out.segment_first.resize(segments);
    for (size_t s = 0; s < segments; ++s) out.segment_first[s] = static_cast<uint32_t>(s);
    return out;
}

}  // namespace

const char* curve_basis_name(CurveBasis b) {
    switch (b) {
        case CurveBasis::BSpline: return "B-spline";
        case CurveBasis::CatmullRom: return "Catmull-Rom";
        case CurveBasis::Bezier: return "Bezier";
        case CurveBasis::Polyline: return "polyline";
    }
    return "?";
}

bool BSplineSegments::is_chain() const {
    for (size_t s = 0; s < segment_first.size(); ++s)
        if (segment_first[s] != s) return false;
    return true;
}

Vec4 BSplineSegments::evaluate(size_t segment, float t) const {
    return eval_bspline(&points[segment_first[segment]], t);
}

size_t min_points(CurveBasis basis, bool closed) {
    switch (basis) {
        case CurveBasis::BSpline:
        case CurveBasis::CatmullRom: return closed ? 3 : 4;
        case CurveBasis::Bezier: return closed ? 3 : 4;
        case CurveBasis::Polyline: return closed ? 3 : 2;
    }
    return 4;
}

bool valid_point_count(CurveBasis basis, size_t n, bool closed) {
    if (n < min_points(basis, closed)) return false;
    if (basis == CurveBasis::Bezier) return closed ? n % 3 == 0 : n % 3 == 1;
    return true;
}

void catmull_rom_to_bspline(const Vec4 cr[4], Vec4 out[4]) { apply(kCatmullRomToBSpline, cr, out); }
void bezier_to_bspline(const Vec4 bz[4], Vec4 out[4]) { apply(kBezierToBSpline, bz, out); }
void bspline_to_bezier(const Vec4 bs[4], Vec4 out[4]) { apply(kBSplineToBezier, bs, out); }

// Uniform Catmull-Rom (tension 1/2): passes through p1 at t = 0 and p2 at t = 1.
Vec4 eval_catmull_rom(const Vec4 p[4], float tf) {
    const double t = tf, t2 = t * t, t3 = t2 * t;
    const double w0 = 0.5 * (-t3 + 2 * t2 - t), w1 = 0.5 * (3 * t3 - 5 * t2 + 2);
    const double w2 = 0.5 * (-3 * t3 + 4 * t2 + t), w3 = 0.5 * (t3 - t2);
    return to_f(w0 * to_d(p[0]) + w1 * to_d(p[1]) + w2 * to_d(p[2]) + w3 * to_d(p[3]));
}

Vec4 eval_bezier(const Vec4 p[4], float tf) {
    const double t = tf, s = 1 - t;
    return to_f(s * s * s * to_d(p[0]) + 3 * s * s * t * to_d(p[1]) + 3 * s * t * t * to_d(p[2]) +
                t * t * t * to_d(p[3]));
}

Vec4 eval_bspline(const Vec4 p[4], float tf) {
    const double t = tf, s = 1 - t, t2 = t * t, t3 = t2 * t;
    const double w0 = s * s * s / 6, w1 = (3 * t3 - 6 * t2 + 4) / 6;
    const double w2 = (-3 * t3 + 3 * t2 + 3 * t + 1) / 6, w3 = t3 / 6;
    return to_f(w0 * to_d(p[0]) + w1 * to_d(p[1]) + w2 * to_d(p[2]) + w3 * to_d(p[3]));
}

std::vector<Vec4> interpolate_bspline(const Vec4* points, size_t n, bool closed) {
    if (n < min_points(CurveBasis::Polyline, closed))
        throw std::invalid_argument("interpolate_bspline: too few points");
    std::vector<D4> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = to_d(points[i]);

    if (!closed) {
        // Natural ends pin c[1] = p[0], c[n] = p[n-1]; rows j = 1..n-2 give
        // c[j] + 4 c[j+1] + c[j+2] = 6 p[j] for the unknowns c[2..n-1] (Thomas algorithm).
        std::vector<D4> c(n + 2);
        c[1] = p[0];
        c[n] = p[n - 1];
        const size_t m = n >= 2 ? n - 2 : 0;  // unknowns c[2..n-1]
        if (m > 0) {
            std::vector<double> diag(m, 4.0);
            std::vector<D4> rhs(m);
            for (size_t k = 0; k < m; ++k) rhs[k] = 6.0 * p[k + 1];
            rhs[0] = rhs[0] - c[1];
            rhs[m - 1] = rhs[m - 1] - c[n];
            for (size_t k = 1; k < m; ++k) {  // forward elimination, off-diagonals are 1
                const double f = 1.0 / diag[k - 1];
                diag[k] -= f;
                rhs[k] = rhs[k] - f * rhs[k - 1];
            }
            c[m + 1] = (1.0 / diag[m - 1]) * rhs[m - 1];
            for (size_t k = m - 1; k-- > 0;) c[k + 2] = (1.0 / diag[k]) * (rhs[k] - c[k + 3]);
        }
        c[0] = 2.0 * c[1] - c[2];
        c[n + 1] = 2.0 * c[n] - c[n - 1];
        std::vector<Vec4> out(n + 2);
        for (size_t i = 0; i < n + 2; ++i) out[i] = to_f(c[i]);
        return out;
    }

    // Closed: cyclic system (1, 4, 1) x = 6 p. Sherman-Morrison: A = T + u v^T with
    // u = (g, 0.., 1), v = (1, 0.., 1/g), T tridiagonal with corners folded into the diagonal.
    const double g = -4.0;  // any g != 0 works; minus the diagonal keeps T diagonally dominant
    std::vector<double> diag(n, 4.0);
    diag[0] -= g;
    diag[n - 1] -= 1.0 / g;
    auto solve_tridiagonal = [&](std::vector<D4> rhs) {
        std::vector<double> d = diag;
        for (size_t k = 1; k < n; ++k) {
            const double f = 1.0 / d[k - 1];
            d[k] -= f;
            rhs[k] = rhs[k] - f * rhs[k - 1];
        }
        std::vector<D4> x(n);
        x[n - 1] = (1.0 / d[n - 1]) * rhs[n - 1];
        for (size_t k = n - 1; k-- > 0;) x[k] = (1.0 / d[k]) * (rhs[k] - x[k + 1]);
        return x;
    };
    std::vector<D4> rhs(n);
    for (size_t i = 0; i < n; ++i) rhs[i] = 6.0 * p[i];
    const std::vector<D4> y = solve_tridiagonal(rhs);
    std::vector<D4> u(n);
    u[0] = {g, g, g, g};
    u[n - 1] = {1, 1, 1, 1};
    const std::vector<D4> z = solve_tridiagonal(u);
    // x = y - z (v.y) / (1 + v.z), per component.
    const D4 vy = y[0] + (1.0 / g) * y[n - 1], vz = z[0] + (1.0 / g) * z[n - 1];
    const D4 f = {vy.x / (1 + vz.x), vy.y / (1 + vz.y), vy.z / (1 + vz.z), vy.w / (1 + vz.w)};
    // Rotate so segment 0 (points c[n-1], c[0], c[1], c[2]) starts at p[0].
    std::vector<Vec4> out(n);
    for (size_t i = 0; i < n; ++i) {
        const size_t k = (i + n - 1) % n;
        const D4 xk = {y[k].x - z[k].x * f.x, y[k].y - z[k].y * f.y, y[k].z - z[k].z * f.z,
                       y[k].w - z[k].w * f.w};
        out[i] = to_f(xk);
    }
    return out;
}

BSplineSegments to_bspline_segments(CurveBasis basis, const Vec4* points, size_t n, bool closed) {
    if (!valid_point_count(basis, n, closed))
        throw std::invalid_argument("to_bspline_segments: " + std::to_string(n) + " points cannot form " +
                                    (closed ? "a closed " : "an open ") + curve_basis_name(basis) + " curve");
    switch (basis) {
        // Already the target basis: copied as a chain.
        case CurveBasis::BSpline:
            return make_chain(std::vector<Vec4>(points, points + n), closed);
        case CurveBasis::Polyline:
            return make_chain(interpolate_bspline(points, n, closed), closed);
        case CurveBasis::CatmullRom: {
            BSplineSegments out;
            const size_t segments = closed ? n : n - 3;
            out.points.reserve(4 * segments);
            out.segment_first.reserve(segments);
            for (size_t s = 0; s < segments; ++s) {
                // Closed segment s runs p[s] -> p[s+1]; open segment s runs p[s+1] -> p[s+2].
                const size_t first = closed ? s + n - 1 : s;
                const Vec4 cr[4] = {points[first % n], points[(first + 1) % n],
                                    points[(first + 2) % n], points[(first + 3) % n]};
                Vec4 cp[4];
                catmull_rom_to_bspline(cr, cp);
                append_segment(out, cp);
            }
            return out;
        }
        // Segments share end points in the file (3k+1 points), never control points here.
        case CurveBasis::Bezier: {
            BSplineSegments out;
            const size_t segments = closed ? n / 3 : (n - 1) / 3;
            out.points.reserve(4 * segments);
            out.segment_first.reserve(segments);
            for (size_t s = 0; s < segments; ++s) {
                const Vec4 bz[4] = {points[3 * s], points[3 * s + 1], points[3 * s + 2],
                                    points[(3 * s + 3) % n]};
                Vec4 cp[4];
                bezier_to_bspline(bz, cp);
                append_segment(out, cp);
            }
            return out;
        }
    }
    return {};
}

}  // namespace purl
