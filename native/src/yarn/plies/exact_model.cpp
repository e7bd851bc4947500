#include "yarn/plies/exact_model.h"

#include <algorithm>
#include <cmath>

namespace purl::plies {
namespace {

struct OffsetTable : PlyOffsets {
    OffsetTable() {
        for (int n = 1; n <= kMaxPlies; ++n)
            for (int i = 0; i < n; ++i) {
                cos[n][i] = std::cos(2 * kPi * i / n);
                sin[n][i] = std::sin(2 * kPi * i / n);
            }
    }
};

// A = a W and its first two derivatives at a knot, for a ply distance a changing at da per m;
// the curvature's own change (dkappa, per m, from the piece's ends) enters the second.
void shared_offset(const Knot& k, float a, float da, Vec3 dkappa, float rate, Vec3 out[6]) {
    const Vec3 w1r = k.w1r - k.wi * rate, w1i = k.w1i + k.wr * rate;
    // N'' = -(kappa.N) kappa - (kappa'.N) T (the same for B), turned by e^{iks}.
    const float kn = dot(k.kv, k.n), kb = dot(k.kv, k.b), dn = dot(dkappa, k.n), db = dot(dkappa, k.b);
    const Vec3 n2 = k.kv * -kn - k.t * dn, b2 = k.kv * -kb - k.t * db;
    const Vec3 w2r = n2 * k.co + b2 * k.si - k.w1i * (2 * rate) - k.wr * (rate * rate);
    const Vec3 w2i = n2 * k.si - b2 * k.co + k.w1r * (2 * rate) - k.wi * (rate * rate);
    out[0] = k.wr * a;
    out[1] = k.wi * a;
    out[2] = k.wr * da + w1r * a;
    out[3] = k.wi * da + w1i * a;
    out[4] = w1r * (2 * da) + w2r * a;
    out[5] = w1i * (2 * da) + w2i * a;
}

}  // namespace

const PlyOffsets& ply_offsets() {
    static const OffsetTable table;
    return table;
}

Quintic Quintic::hermite(Vec3 p0, Vec3 d0, Vec3 a0, Vec3 p1, Vec3 d1, Vec3 a1, float h) {
    const Vec3 D0 = d0 * h, A0 = a0 * (h * h), D1 = d1 * h, A1 = a1 * (h * h);
    const Vec3 delta = p1 - p0 - D0 - A0 * 0.5f, slope = D1 - D0 - A0, bend = A1 - A0;
    return {{p0, D0, A0 * 0.5f, delta * 10.0f - slope * 4.0f + bend * 0.5f, slope * 7.0f - delta * 15.0f - bend,
             delta * 6.0f - slope * 3.0f + bend * 0.5f}};
}

void YarnModel::ply(int i, int j, PlyPoly& out) const {
    const Piece& q = piece[j];
    const float cp = cos_offset[i], sp = sin_offset[i];
    float c[3][6];
    for (int k = 0; k < 6; ++k) {
        c[0][k] = ply_coefficient(q.centre.k[k].x, q.ar.k[k].x, q.ai.k[k].x, cp, sp);
        c[1][k] = ply_coefficient(q.centre.k[k].y, q.ar.k[k].y, q.ai.k[k].y, cp, sp);
        c[2][k] = ply_coefficient(q.centre.k[k].z, q.ar.k[k].z, q.ai.k[k].z, cp, sp);
    }
    out.x.set(c[0]);
    out.y.set(c[1]);
    out.z.set(c[2]);
    out.s0 = q.s0;
    out.inv_h = q.inv_h;
    out.r0 = ply_radius * q.r0;
    out.dr = ply_radius * (q.r1 - q.r0);
    out.piece = j;
}

void make_knot(const CurvePoint& c, double g, float s, const YarnModel& m, Knot& k) {
    k.g = g;
    k.s = s;
    k.inv_speed = 1.0f / std::max(c.speed, 1e-30f);
    k.radius = c.radius;
    k.kappa = length(c.curvature);
    k.c = m.local(c.position - m.origin);
    k.t = m.local(c.tangent);
    k.kv = m.local(c.curvature);
    k.n = m.local(c.normal);
    k.b = m.local(c.binormal);
    k.co = std::cos(m.rate * c.arc_length);
    k.si = std::sin(m.rate * c.arc_length);
    k.wr = k.n * k.co + k.b * k.si;
    k.wi = k.n * k.si - k.b * k.co;
    // dN/ds = -(kappa.N) T, dB/ds = -(kappa.B) T.
    const float kn = dot(c.curvature, c.normal), kb = dot(c.curvature, c.binormal);
    k.w1r = k.t * -(kn * k.co + kb * k.si);
    k.w1i = k.t * -(kn * k.si - kb * k.co);
}

void make_piece(const Knot& a, const Knot& b, const YarnModel& m, Piece& q) {
    q.s0 = a.s;
    q.h = std::max(b.s - a.s, 1e-12f);
    q.inv_h = 1.0f / q.h;
    q.g0 = a.g;
    q.g1 = b.g;
    q.dg0 = a.inv_speed * q.h;
    q.dg1 = b.inv_speed * q.h;
    q.r0 = a.radius;
    q.r1 = b.radius;
    q.kappa = std::max(a.kappa, b.kappa);
    q.centre = Quintic::hermite(a.c, a.t, a.kv, b.c, b.t, b.kv, q.h);
    const Vec3 dkappa = (b.kv - a.kv) * q.inv_h;
    const float da = m.distance * (b.radius - a.radius) * q.inv_h;
    Vec3 ea[6], eb[6];
    shared_offset(a, m.distance * a.radius, da, dkappa, m.rate, ea);
    shared_offset(b, m.distance * b.radius, da, dkappa, m.rate, eb);
    q.ar = Quintic::hermite(ea[0], ea[2], ea[4], eb[0], eb[2], eb[4], q.h);
    q.ai = Quintic::hermite(ea[1], ea[3], ea[5], eb[1], eb[3], eb[5], q.h);
}

}  // namespace purl::plies
