// The exact method's model of the yarn over the stretch a ray crosses, in the ray's own
// coordinates: origin at the tube entry, z along the ray, x along the cutting plane's normal
// (across the ray and the yarn), y = z cross x. The ray is the z axis, so a ply centre's (x, y)
// is its offset across the ray and z its distance along it.
//
// Ply i is C(s) + Re[e^{i phi_i} A(s)] with phi_i = 2 pi i / N and A = a (N - iB) e^{i k s}
// shared by all plies (a: ply distance, k: ply turn rate). Over each piece between two exact
// frames (knots), C and A are quintic Hermite interpolants in arc length (value, first and
// second derivative at both ends; the frame's derivatives from the rotation-minimizing law
// dN/ds = -(kappa.N) T), so each ply is one quintic per axis: its coefficients are
// C_j + cos(phi_i) Re A_j - sin(phi_i) Im A_j, and everything after that is polynomial
// arithmetic. On straight yarns the model is exact to rounding; on bends its error is that of
// quintic Hermite interpolation, h^6 |f^(6)| / 46080 (for a piece of 2 R on a bend of radius
// 2 R, with the frame turning at up to k + kappa, below 1e-3 R). Cloth's curvature changes
// within a piece, and there the model is off by up to ~0.05 R: PlyTraceOptions::model_margin.
#pragma once
#include "yarn/plies/result.h"

namespace purl::plies {

constexpr int kMaxPieces = 32;  // model pieces over the ray's stretch (exact frames: one more)

// cos and sin of every ply's fixed phase offset 2 pi i / N, for every N up to kMaxPlies.
struct PlyOffsets {
    float cos[kMaxPlies + 1][kMaxPlies], sin[kMaxPlies + 1][kMaxPlies];
};
const PlyOffsets& ply_offsets();  // built once (thread-safe static)

struct Quintic {
    Vec3 k[6];  // in v = u / h, u the arc length from the piece's start

    static Quintic hermite(Vec3 p0, Vec3 d0, Vec3 a0, Vec3 p1, Vec3 d1, Vec3 a1, float h);
};

// Coefficient j of one ply's quintic from the pieces' shared ones: the centre-line's plus the
// offset turned by the ply's phase (cp, sp: its cosine and sine).
inline float ply_coefficient(float centre, float ar, float ai, float cp, float sp) { return centre + ar * cp - ai * sp; }

// A polynomial of `degree` at v by Horner's rule; k(j) gives coefficient j.
template <int degree, class Coefficients>
inline float horner(const Coefficients& k, float v) {
    float p = k(degree);
    for (int j = degree - 1; j >= 0; --j) p = p * v + k(j);
    return p;
}

// A quintic in v with its derivative's and second derivative's coefficients.
struct Axis {
    float k[6], d[5], dd[4];

    void set(const float* c) {
        for (int j = 0; j < 6; ++j) k[j] = c[j];
        for (int j = 0; j < 5; ++j) d[j] = float(j + 1) * c[j + 1];
        for (int j = 0; j < 4; ++j) dd[j] = float((j + 1) * (j + 2)) * c[j + 2];
    }
    void eval(float v, float& p, float& dp, float& ddp) const {
        p = horner<5>([&](int j) { return k[j]; }, v);
        dp = horner<4>([&](int j) { return d[j]; }, v);
        ddp = horner<3>([&](int j) { return dd[j]; }, v);
    }
};

// The model's ply centre at one arc length: position, d/ds and d2/ds2 in model coordinates.
struct ModelPoint {
    Vec3 p, d, dd;
    float ply_radius;  // m
};

// One ply's centre over one piece: a quintic in v per axis.
struct PlyPoly {
    Axis x, y, z;
    float s0, inv_h;  // the piece's start (arc length from the window's start) and 1 / length
    float r0, dr;     // ply radius at the start and its change over the piece, m
    int piece;

    ModelPoint at(float s) const {
        const float v = (s - s0) * inv_h;
        ModelPoint m;
        x.eval(v, m.p.x, m.d.x, m.dd.x);
        y.eval(v, m.p.y, m.d.y, m.dd.y);
        z.eval(v, m.p.z, m.d.z, m.dd.z);
        m.d *= inv_h;
        m.dd *= inv_h * inv_h;
        m.ply_radius = r0 + dr * v;
        return m;
    }
};

// An exact frame of the yarn, in the model's terms (no member initializers: every field is set).
struct Knot {
    double g;         // curve parameter (unwrapped on loops)
    float s;          // arc length from the first knot evaluated, continuous across a loop's seam
    float inv_speed;  // dg/ds
    float radius;     // yarn radius R, m
    float kappa;      // |curvature|, 1/m
    Vec3 c, t, kv;    // centre, tangent, curvature vector
    Vec3 n, b;        // normal and binormal
    Vec3 wr, wi;      // W = (N - iB) e^{iks}
    Vec3 w1r, w1i;    // (N' - iB') e^{iks}: the frame's own turn toward the tangent
    float co, si;     // cos and sin of k s
};

// No member initializers: a query's array of pieces is left uninitialized until built.
struct Piece {
    float s0, h, inv_h;  // arc length at the start (from the first knot evaluated), length
    double g0, g1;       // curve parameters at the ends
    float dg0, dg1;      // dg/dv at the ends
    float r0, r1;        // yarn radius at the ends
    float kappa;         // largest curvature at the ends, 1/m
    Quintic centre, ar, ai;  // C and A = a W

    // Curve parameter at v (cubic Hermite through the ends' g and dg/dv).
    double g(float v) const {
        const double v2 = double(v) * v, v3 = v2 * v;
        return (2 * v3 - 3 * v2 + 1) * g0 + (v3 - 2 * v2 + v) * dg0 + (-2 * v3 + 3 * v2) * g1 + (v3 - v2) * dg1;
    }
};

struct YarnModel {
    Vec3 origin, ex, ey, ez;  // model coordinates: origin and axes in world space
    float distance = 0, ply_radius = 0;  // ply_distance and ply_radius of the description (in R)
    float rate = 0;                      // k, rad/m
    int pieces = 0;
    Slots<Piece, kMaxPieces> piece;  // left uninitialized until built
    int built_lo = kMaxPieces, built_hi = -1;  // the pieces built so far (contiguous)
    int plies = 0;
    const float* cos_offset = nullptr;  // cos and sin of 2 pi i / N
    const float* sin_offset = nullptr;

    Vec3 local(Vec3 v) const { return {dot(v, ex), dot(v, ey), dot(v, ez)}; }

    // Ply i over piece j, written in place (a returned copy of ~200 bytes showed in the profile).
    void ply(int i, int j, PlyPoly& out) const;
    // Curve parameter at arc length s, from piece j's map (extrapolated a little past its ends).
    double g(int j, float s) const { return piece[j].g((s - piece[j].s0) * piece[j].inv_h); }
};

// Written in place: a query's knots are slots of an array.
void make_knot(const CurvePoint& c, double g, float s, const YarnModel& m, Knot& k);
void make_piece(const Knot& a, const Knot& b, const YarnModel& m, Piece& q);

}  // namespace purl::plies
