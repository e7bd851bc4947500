#include "yarn/plies/exact_scan.h"

#include <algorithm>
#include <cmath>

namespace purl::plies {

void PieceGrid::set(const Piece& q, const float* cp, const float* sp, int plies) {
    const int n = padded_plies(plies);
    for (int j = 0; j < 6; ++j) {
        const Vec3 c = q.centre.k[j], ar = q.ar.k[j], ai = q.ai.k[j];
        for (int i = 0; i < n; ++i) {
            x[j][i] = ply_coefficient(c.x, ar.x, ai.x, cp[i], sp[i]);
            y[j][i] = ply_coefficient(c.y, ar.y, ai.y, cp[i], sp[i]);
        }
    }
    // The derivatives' coefficients, as Axis::set.
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < n; ++i) x[6 + j][i] = float(j + 1) * x[j + 1][i], y[6 + j][i] = float(j + 1) * y[j + 1][i];
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < n; ++i) {
            const float k = float((j + 1) * (j + 2));
            x[11 + j][i] = k * x[j + 2][i], y[11 + j][i] = k * y[j + 2][i];
        }
}

void PieceGrid::node(int plies, float v, float ih, int to) {
    const int n = padded_plies(plies);
    const float ih2 = ih * ih;
    float* __restrict out_d = D[to];
    float* __restrict out_f = f[to];
    float* __restrict out_slope = slope[to];
    for (int i = 0; i < n; ++i) {
        const auto x_at = [&](int first) { return [&, first](int j) { return x[first + j][i]; }; };
        const auto y_at = [&](int first) { return [&, first](int j) { return y[first + j][i]; }; };
        const CrossingTerms c = crossing_terms(horner<5>(x_at(0), v), horner<4>(x_at(6), v), horner<3>(x_at(11), v),
                                               horner<5>(y_at(0), v), horner<4>(y_at(6), v), horner<3>(y_at(11), v));
        out_d[i] = c.D;
        out_f[i] = c.f * ih;
        out_slope[i] = c.slope * ih2;  // sample() scales by ih twice: equal to rounding
    }
}

void Brackets::bound(const YarnModel& m, const Piece& q) {
    // From the curvature (a quarter over the ends' largest, with 5-10% to spare) and the turn rate.
    const float kappa = 1.25f * q.kappa, a = m.distance * std::max(q.r0, q.r1), k = std::fabs(m.rate);
    speed = 1.05f * std::sqrt(sqr(1 + a * kappa) + sqr(a * k));
    accel = 1.1f * (kappa * (1 + a * kappa) + a * (k * k + 2 * k * kappa));
}

void Brackets::interval(int ply, const Sampled& a, const Sampled& b, int depth) {
    if (out_of_reach(a.s, a.D, b.s, b.D, reach2, speed, accel)) return;
    if (a.f < 0 && b.f >= 0) {
        if (count < kMaxWork) work[count++] = {ply, a, b};
        return;
    }
    if ((a.f < 0) != (b.f < 0) || depth >= 2) return;
    // Ends of one sign: where the cubic through the ends' values and slopes turns back toward
    // zero (within a quarter of the ends' size), split there and look again.
    const float h = b.s - a.s, p = a.slope * h, q = b.slope * h;
    const float k3 = 2 * (a.f - b.f) + p + q, k2 = 3 * (b.f - a.f) - 2 * p - q;
    const float c2 = 3 * k3, c1 = 2 * k2, c0 = p;
    float roots[2];
    int n = 0;
    if (std::fabs(c2) > 1e-12f * (std::fabs(c1) + std::fabs(c0))) {
        const float disc = c1 * c1 - 4 * c2 * c0;
        if (disc >= 0) {
            roots[n++] = (-c1 - std::sqrt(disc)) / (2 * c2);
            roots[n++] = (-c1 + std::sqrt(disc)) / (2 * c2);
        }
    } else if (c1 != 0) {
        roots[n++] = -c0 / c1;
    }
    const float sign = a.f < 0 ? -1.0f : 1.0f, margin = 0.25f * std::min(std::fabs(a.f), std::fabs(b.f));
    float u = -1;
    for (int i = 0; i < n; ++i) {
        const float r = roots[i];
        if (r > 0 && r < 1 && (((k3 * r + k2) * r + p) * r + a.f) * sign < margin) u = r;
    }
    if (u < 0) return;
    const Sampled mid = sample((*polys)[ply], a.s + h * clamp(u, 0.1f, 0.9f));
    interval(ply, a, mid, depth + 1);
    interval(ply, mid, b, depth + 1);
}

bool solve(const PlyPoly& q, const Work& w, float tolerance, int max_steps, float& s) {
    float lo = w.lo.s, hi = w.hi.s;
    s = lo + (hi - lo) * clamp(w.lo.f / (w.lo.f - w.hi.f), 0.0f, 1.0f);
    if (!std::isfinite(s)) s = 0.5f * (lo + hi);
    const float rising = w.lo.f <= 0 ? 1.0f : -1.0f;
    for (int step = 0; step <= max_steps; ++step) {
        const Sampled o = sample(q, s);
        float next = s - o.f / o.slope;
        const bool newton = o.slope * rising > 0;
        if (newton && std::fabs(next - s) < tolerance) return true;
        if (step == max_steps) break;
        if (o.f * rising < 0) lo = s;
        else hi = s;
        if (hi - lo < tolerance) return true;
        if (!newton || !(next >= lo && next <= hi)) next = 0.5f * (lo + hi);
        s = next;
    }
    return false;
}

}  // namespace purl::plies
