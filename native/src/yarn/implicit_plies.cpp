#include "yarn/implicit_plies.h"

#include <algorithm>
#include <cmath>

#include "yarn/yarn_tube.h"

namespace purl {
namespace {

// Ray (from the tube entry) against an infinite cylinder; false when it misses.
bool intersect_cylinder(Vec3 origin, Vec3 direction, Vec3 axis_point, Vec3 axis, float radius, float& enter,
                        float& leave) {
    const Vec3 w = origin - axis_point;
    const Vec3 w_perp = w - axis * dot(w, axis);
    const Vec3 d_perp = direction - axis * dot(direction, axis);
    const float a = dot(d_perp, d_perp), b = dot(w_perp, d_perp), c = dot(w_perp, w_perp) - radius * radius;
    if (a < 1e-12f) {  // running along the ply: inside or not at all
        if (c > 0) return false;
        enter = 0;
        leave = 1e30f;
        return true;
    }
    const float disc = b * b - a * c;
    if (disc < 0) return false;
    const float root = std::sqrt(disc);
    enter = (-b - root) / a;
    leave = (-b + root) / a;
    return leave > 0;
}

// Fixed-size scratch arrays left uninitialized: the per-query arrays below hold kilobytes of
// CurvePoints whose default member initializers would otherwise be zeroed on every query (a
// measurable share of a side-view query). Only trivially copyable aggregates are stored.
template <class T, int N>
struct Slots {
    union {
        T items[N];
    };
    Slots() {}
    T& operator[](int i) { return items[i]; }
    const T& operator[](int i) const { return items[i]; }
};

// One ply's centre-line at one cross-section of the yarn. The position along the curve is
// an unwrapped parameter g = segment + t: loops may run past their seam, open curves stop at
// their ends.
struct PlyCut {
    double g = 0;
    uint32_t segment = 0;
    float t = 0;
    CurvePoint yarn;
    PlyCentre centre;
};

void locate(const CachedCurve& frames, double g, uint32_t& segment, float& t) {
    const double n = frames.segment_count();
    if (frames.closed()) {
        if (!(std::fabs(g) < n)) g = std::fmod(g, n);  // fmod would return g as it is
        if (g < 0) g += n;
    } else {
        g = std::min(std::max(g, 0.0), n);
    }
    segment = std::min(static_cast<uint32_t>(g), frames.segment_count() - 1);
    t = static_cast<float>(g - segment);
}

PlyCut cut_at(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply, double g) {
    PlyCut cut;
    cut.g = g;
    locate(frames, g, cut.segment, cut.t);
    cut.yarn = frames.evaluate(cut.segment, cut.t);
    cut.centre = ply_centre(cut.yarn, d, tw, ply);
    return cut;
}

struct Candidate {
    int ply = 0;
    PlyCut cut;
    float enter = 0, leave = 0;  // ray distances from the tube entry, m
    float approach = 0;          // ray distance of the closest approach to the ply centre-line, m
    bool fixed = false;          // from the circular fallback: `enter` is final
};

// The ply surface point, frame and coordinates for a hit at `point`.
PlyHit finish_hit(const Candidate& c, Vec3 point, const YarnTwist& tw, const YarnTubeHit& hit) {
    PlyHit h;
    h.hit = true;
    h.ply = c.ply;
    h.point = point;
    h.distance = std::max(c.enter, 0.0f);
    h.tangent = normalize(c.cut.centre.derivative);
    Vec3 radial = point - c.cut.centre.position;
    radial -= h.tangent * dot(radial, h.tangent);
    h.outward = c.cut.centre.outward - h.tangent * dot(c.cut.centre.outward, h.tangent);
    h.outward = normalize(h.outward);
    const float len = length(radial);
    // A hit on the ply's axis (only with a degenerate ray) faces the viewer.
    h.normal = len > 1e-12f ? radial / len : normalize(-hit.direction - h.tangent * dot(-hit.direction, h.tangent));
    if (!is_finite(h.normal)) h.normal = h.outward;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.v_ply = c.cut.yarn.arc_length * tw.ply_stretch;
    h.u_yarn = CurveFrames::azimuth(c.cut.yarn, point);
    h.v_yarn = c.cut.yarn.arc_length;
    h.arrangement_azimuth = wrap_angle(h.u_yarn - ply_phase(tw, c.cut.yarn.arc_length));
    h.segment = c.cut.segment;
    h.t = c.cut.t;
    return h;
}

PlyHit pass_through(const YarnTubeHit& hit, float exit_distance) {
    PlyHit h;
    h.exit_distance = exit_distance;
    h.point = hit.point + hit.direction * h.exit_distance;
    return h;
}

PlyHit pass_through(const CurveFrames& frames, const YarnTubeHit& hit, uint32_t segment, float t) {
    return pass_through(hit, tube_chord_length(frames, segment, t, hit.point, hit.direction));
}

// The same when `at` is the projection of the tube entry itself (not of a neighbouring point).
template <class Curve>  // CurveFrames, or a query's CachedCurve
PlyHit pass_through(const Curve& frames, const YarnTubeHit& hit, const CentrelineProjection& at) {
    return pass_through(hit, tube_exit(frames, at, hit.point, hit.direction).distance);
}

// A ray passing this close (in tolerances) outside a ply still touches it: the explicit
// reference counts a hit within 1e-5 R of the surface.
constexpr float kGraze = 0.1f;

constexpr int kMaxPlies = 16;   // plies with a precomputed phase offset (descriptions allow 12)
constexpr int kMaxPieces = 32;  // model pieces over the ray's stretch (exact frames: one more)
constexpr int kSubsteps = 2;    // grid steps per piece at which every ply is checked
constexpr int kMaxWork = 64;    // model crossings solved per query at most

// cos and sin of every ply's fixed phase offset 2 pi i / N, for every N up to kMaxPlies: built
// once (thread-safe static), instead of 2N calls to cos and sin per query.
struct PlyOffsets {
    float cos[kMaxPlies + 1][kMaxPlies], sin[kMaxPlies + 1][kMaxPlies];
    PlyOffsets() {
        for (int n = 1; n <= kMaxPlies; ++n)
            for (int i = 0; i < n; ++i) {
                cos[n][i] = std::cos(2 * kPi * i / n);
                sin[n][i] = std::sin(2 * kPi * i / n);
            }
    }
};
const PlyOffsets& ply_offsets() {
    static const PlyOffsets table;
    return table;
}

// ---- The local model: the yarn over the ray's stretch in the ray's own coordinates ----------
// Coordinates: origin at the tube entry, z along the ray, x along the cutting plane's normal
// (across the ray and the yarn), y = z cross x. The ray is the z axis, so a ply centre's (x, y)
// is its offset across the ray and z its distance along it.
//
// Ply i is C(s) + Re[e^{i phi_i} A(s)] with phi_i = 2 pi i / N and A = a (N - iB) e^{i k s}
// shared by all plies (a: ply distance, k: ply turn rate). Over each piece between two exact
// frames, C and A are quintic Hermite interpolants in arc length (value, first and second
// derivative at both ends; the frame's derivatives from the rotation-minimizing law
// dN/ds = -(kappa.N) T), so each ply is one quintic per axis: its coefficients are
// C_j + cos(phi_i) Re A_j - sin(phi_i) Im A_j, and everything after that is polynomial
// arithmetic. On straight yarns the model is exact to rounding; on bends its error is that of
// quintic Hermite interpolation, h^6 |f^(6)| / 46080 (for a piece of 2 R on a bend of radius
// 2 R, with the frame turning at up to k + kappa, below 1e-3 R). Cloth's curvature changes
// within a piece, and there the model is off by up to ~0.05 R: PlyTraceOptions::model_margin.

struct Quintic {
    Vec3 k[6];  // in v = u / h, u the arc length from the piece's start

    static Quintic hermite(Vec3 p0, Vec3 d0, Vec3 a0, Vec3 p1, Vec3 d1, Vec3 a1, float h) {
        const Vec3 D0 = d0 * h, A0 = a0 * (h * h), D1 = d1 * h, A1 = a1 * (h * h);
        const Vec3 delta = p1 - p0 - D0 - A0 * 0.5f, slope = D1 - D0 - A0, bend = A1 - A0;
        return {{p0, D0, A0 * 0.5f, delta * 10.0f - slope * 4.0f + bend * 0.5f,
                 slope * 7.0f - delta * 15.0f - bend, delta * 6.0f - slope * 3.0f + bend * 0.5f}};
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

// The model's ply centre at one arc length: position, d/ds and d2/ds2 in model coordinates.
struct ModelPoint {
    Vec3 p, d, dd;
    float ply_radius;  // m
};

// A quintic in v with its derivative's and second derivative's coefficients.
struct Axis {
    float k[6], d[5], dd[4];

    void set(const float* c) {
        for (int j = 0; j < 6; ++j) k[j] = c[j];
        for (int j = 0; j < 5; ++j) d[j] = float(j + 1) * c[j + 1];
        for (int j = 0; j < 4; ++j) dd[j] = float((j + 1) * (j + 2)) * c[j + 2];
    }
    void eval(float v, float& p, float& dp, float& ddp) const {
        p = ((((k[5] * v + k[4]) * v + k[3]) * v + k[2]) * v + k[1]) * v + k[0];
        dp = (((d[4] * v + d[3]) * v + d[2]) * v + d[1]) * v + d[0];
        ddp = ((dd[3] * v + dd[2]) * v + dd[1]) * v + dd[0];
    }
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

struct LocalYarn {
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
    void ply(int i, int j, PlyPoly& out) const {
        const Piece& q = piece[j];
        const float cp = cos_offset[i], sp = sin_offset[i];
        float c[3][6];
        for (int k = 0; k < 6; ++k) {
            const Vec3 v = q.centre.k[k] + q.ar.k[k] * cp - q.ai.k[k] * sp;
            c[0][k] = v.x;
            c[1][k] = v.y;
            c[2][k] = v.z;
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
    // Curve parameter at arc length s, from piece j's map (extrapolated a little past its ends).
    double g(int j, float s) const { return piece[j].g((s - piece[j].s0) * piece[j].inv_h); }
};

// Written in place: a query's knots are slots of an array.
void make_knot(const CurvePoint& c, double g, float s, const LocalYarn& m, Knot& k) {
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

void make_piece(const Knot& a, const Knot& b, const LocalYarn& m, Piece& q) {
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

// ---- Crossings on the model ---------------------------------------------------------------
// Per ply, f(s) is the function whose roots are its crossings: in the ply plane
// f = p.p' across the ray (rising roots: closest approaches, D = |p|^2 across the ray is the
// squared miss distance); in the yarn plane f = p.x (any sign change: the centre-line pierces
// the plane). Every ply is checked at grid nodes kSubsteps per piece; an interval holds a
// crossing when f changes sign, or two when the cubic through its ends' values and slopes
// turns back across zero (a ray grazing a ply between two close approaches).

struct Sampled {
    float s, D, f, slope;  // arc length, D, f and df/ds
};

// D, f and df/ds of one ply at arc length s (only the axes across the ray).
Sampled sample(const PlyPoly& q, float s, bool ply_plane) {
    const float v = (s - q.s0) * q.inv_h, ih = q.inv_h;
    float px, dx, ddx, py, dy, ddy;
    q.x.eval(v, px, dx, ddx);
    q.y.eval(v, py, dy, ddy);
    if (!ply_plane) return {s, 0, px, dx * ih};
    return {s, px * px + py * py, (px * dx + py * dy) * ih, (dx * dx + dy * dy + px * ddx + py * ddy) * ih * ih};
}

// A lower bound on D over [a, b] above reach2 proves the ply out of the ray's reach there: D
// can fall from each end no faster than the bound on its second derivative allows (D' = 0 at an
// interior minimum); speed and accel bound |p'| and |p''|.
inline bool out_of_reach(float s_a, float D_a, float s_b, float D_b, float reach2, float speed, float accel) {
    const float h = s_b - s_a;
    // |d2D/ds2| = 2 |p'^2 + p.p''| with |p| at most the larger end's plus half the travel.
    const float p = std::sqrt(std::max(D_a, D_b)) + 0.5f * speed * h;
    const float curvature2 = 2 * (speed * speed + p * accel);
    const float t = std::min(std::max((D_a - D_b) / (curvature2 * h) + 0.5f * h, 0.0f), h);
    // Branch-free (the grid's loop over plies vectorizes): both ends and the bound beyond reach.
    return (D_a > reach2) & (D_b > reach2) & (D_a - 0.5f * curvature2 * t * t > reach2);
}

// Every ply of one piece, coefficient-major (coefficient j of ply i at [j][i]: the quintic, its
// derivative, its second derivative), so the grid's loops over plies vectorize. Ply counts are
// padded to a multiple of 4 with copies of ply 0 (their results are never read).
struct PieceGrid {
    float x[15][kMaxPlies], y[15][kMaxPlies];
    float D[2][kMaxPlies], f[2][kMaxPlies], slope[2][kMaxPlies];  // at the previous and latest node

    static int padded(int plies) { return (plies + 3) & ~3; }
    // The coefficients LocalYarn::ply gives (the same arithmetic), straight from the piece,
    // every ply at once; cp, sp: cos and sin of each ply's offset, padded like the plies.
    void set(const Piece& q, const float* cp, const float* sp, int plies) {
        const int n = padded(plies);
        for (int j = 0; j < 6; ++j) {
            const Vec3 c = q.centre.k[j], ar = q.ar.k[j], ai = q.ai.k[j];
            for (int i = 0; i < n; ++i) {
                x[j][i] = c.x + ar.x * cp[i] - ai.x * sp[i];
                y[j][i] = c.y + ar.y * cp[i] - ai.y * sp[i];
            }
        }
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < n; ++i) x[6 + j][i] = float(j + 1) * x[j + 1][i], y[6 + j][i] = float(j + 1) * y[j + 1][i];
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < n; ++i) {
                const float k = float((j + 1) * (j + 2));
                x[11 + j][i] = k * x[j + 2][i], y[11 + j][i] = k * y[j + 2][i];
            }
    }
    // Every ply at v into slot `to` (0 or 1).
    void node(int plies, float v, float ih, bool ply_plane, int to) {
        const int n = padded(plies);
        const float ih2 = ih * ih;
        float px[kMaxPlies], dx[kMaxPlies], ddx[kMaxPlies], py[kMaxPlies], dy[kMaxPlies], ddy[kMaxPlies];
        for (int i = 0; i < n; ++i) {
            px[i] = ((((x[5][i] * v + x[4][i]) * v + x[3][i]) * v + x[2][i]) * v + x[1][i]) * v + x[0][i];
            dx[i] = (((x[10][i] * v + x[9][i]) * v + x[8][i]) * v + x[7][i]) * v + x[6][i];
            ddx[i] = ((x[14][i] * v + x[13][i]) * v + x[12][i]) * v + x[11][i];
            py[i] = ((((y[5][i] * v + y[4][i]) * v + y[3][i]) * v + y[2][i]) * v + y[1][i]) * v + y[0][i];
            dy[i] = (((y[10][i] * v + y[9][i]) * v + y[8][i]) * v + y[7][i]) * v + y[6][i];
            ddy[i] = ((y[14][i] * v + y[13][i]) * v + y[12][i]) * v + y[11][i];
        }
        // What sample() gives, one branch-free loop per plane.
        float *out_d = D[to], *out_f = f[to], *out_slope = slope[to];
        if (ply_plane) {
            for (int i = 0; i < n; ++i) {
                out_d[i] = px[i] * px[i] + py[i] * py[i];
                out_f[i] = (px[i] * dx[i] + py[i] * dy[i]) * ih;
                out_slope[i] = (dx[i] * dx[i] + dy[i] * dy[i] + px[i] * ddx[i] + py[i] * ddy[i]) * ih2;
            }
        } else {
            for (int i = 0; i < n; ++i) {
                out_d[i] = 0;
                out_f[i] = px[i];
                out_slope[i] = dx[i] * ih;
            }
        }
    }
};

struct Work {
    int ply;
    Sampled lo, hi;  // a bracket of one crossing
};

// The current piece's plies as PlyPolys, each built when first asked for (the grid has its own
// copy of the coefficients; only plies with work need these).
struct PiecePlies {
    const LocalYarn* model = nullptr;
    int piece = 0;
    uint32_t built = 0;
    Slots<PlyPoly, kMaxPlies> items;  // left uninitialized until built

    void reset(const LocalYarn& m, int j) {
        model = &m;
        piece = j;
        built = 0;
    }
    const PlyPoly& operator[](int i) {
        if (!(built >> i & 1)) {
            model->ply(i, piece, items[i]);
            built |= 1u << i;
        }
        return items[i];
    }
};

struct Search {
    PiecePlies* polys;  // the current piece's plies
    bool ply_plane;
    float reach2;        // (ply radius + model margin)^2: a closer approach may be a crossing
    float speed, accel;  // bounds on |p'| and |p''| over the current piece (ply plane)
    Work work[kMaxWork];
    int count = 0;

    Search(bool plane) : polys(nullptr), ply_plane(plane), reach2(0), speed(0), accel(0) {}

    void interval(int ply, const Sampled& a, const Sampled& b, int depth) {
        if (ply_plane && out_of_reach(a.s, a.D, b.s, b.D, reach2, speed, accel)) return;
        const bool crossing = ply_plane ? (a.f < 0 && b.f >= 0) : ((a.f <= 0) != (b.f <= 0));
        if (crossing) {
            if (count < kMaxWork) work[count++] = {ply, a, b};
            return;
        }
        if ((a.f < 0) != (b.f < 0) || depth >= 2) return;
        // Ends of one sign: where the cubic through the ends' values and slopes turns back
        // toward zero (within a quarter of the ends' size), split there and look again.
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
        const Sampled mid = sample((*polys)[ply], a.s + h * clamp(u, 0.1f, 0.9f), ply_plane);
        interval(ply, a, mid, depth + 1);
        interval(ply, mid, b, depth + 1);
    }
};

// Bounds on a ply centre's speed and acceleration over a piece, for out_of_reach: from
// the curvature (a quarter over the ends' largest, with 5-10% to spare) and the turn rate.
void piece_bounds(const LocalYarn& m, const Piece& q, Search& search) {
    const float kappa = 1.25f * q.kappa, a = m.distance * std::max(q.r0, q.r1), k = std::fabs(m.rate);
    search.speed = 1.05f * std::sqrt(sqr(1 + a * kappa) + sqr(a * k));
    search.accel = 1.1f * (kappa * (1 + a * kappa) + a * (k * k + 2 * k * kappa));
}

// Safeguarded Newton steps on the model inside a bracket, from the secant point. False when
// max_steps are not enough.
bool solve(const PlyPoly& q, const Work& w, bool ply_plane, float tolerance, int max_steps, float& s) {
    float lo = w.lo.s, hi = w.hi.s;
    s = lo + (hi - lo) * clamp(w.lo.f / (w.lo.f - w.hi.f), 0.0f, 1.0f);
    if (!std::isfinite(s)) s = 0.5f * (lo + hi);
    const float rising = w.lo.f <= 0 ? 1.0f : -1.0f;
    for (int step = 0; step <= max_steps; ++step) {
        const Sampled o = sample(q, s, ply_plane);
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

// Newton step (m of yarn) toward the point of a ply centre-line closest to x: the root of
// (P - x).P', with derivative |P'|^2 + (P - x).P''.
float closest_point_step(Vec3 position, Vec3 d1, Vec3 d2, Vec3 x) {
    const Vec3 w = position - x;
    const float slope = dot(d1, d1) + dot(w, d2);
    return -dot(w, d1) / std::max(slope, 0.25f * dot(d1, d1));
}

// A crossing found on the model, with where the ray enters the ply there (model estimates).
struct ModelCandidate {
    int ply, piece, piece_enter;  // pieces of the crossing and of the entry
    float s_cross, s_enter;  // model arc lengths of the crossing and of the helix point nearest the entry
    float s_lo, s_hi;        // the crossing's bracket
    float approach, enter;   // ray distances of the closest approach and of the entry, m
    float slack;             // how much earlier the exact entry could be, m
    float miss;              // model miss distance less the ply radius, m
    bool ambiguous;          // the miss distance is within the model's margin of the ply radius
};

// The ply's model at arc length s, moving q to the built piece that holds s (the end pieces of
// what is built extrapolate).
ModelPoint model_at(const LocalYarn& m, int ply, PlyPoly& q, float s) {
    for (int hop = 0; hop < kMaxPieces; ++hop) {
        const float v = (s - q.s0) * q.inv_h;
        if (v < 0 && q.piece > m.built_lo) m.ply(ply, q.piece - 1, q);
        else if (v > 1 && q.piece < m.built_hi) m.ply(ply, q.piece + 1, q);
        else break;
    }
    return q.at(s);
}

// The ray's entry into the ply near a crossing, on the model: the cylinder along the tangent
// there, moved to the cylinder at the helix point closest to the entry (what enter_ply does on
// the exact curve). Returns the entry distance; `s` ends at the helix point nearest it, in
// piece q.piece. When the entry moves too far past the window's ends for the model,
// `trusted` is false and `s` stays at the crossing (the exact refinement's start).
float model_entry(const LocalYarn& m, int ply, PlyPoly& q, float approach, float tolerance, int refinements,
                  float max_shift, float& s, float& cos_incidence, bool& trusted) {
    const float crossing = s;
    const int start_piece = q.piece;
    ModelPoint p = q.at(s);
    const Vec3 o(0.0f), z(0, 0, 1);
    float enter, leave;
    bool hits = intersect_cylinder(o, z, p.p, normalize(p.d), p.ply_radius, enter, leave);
    float lambda = hits ? clamp(enter, 0.0f, approach) : approach;
    for (int r = 0; r < refinements; ++r) {
        const float ds = clamp(closest_point_step(p.p, p.d, p.dd, z * lambda), -max_shift, max_shift);
        if (hits && std::fabs(ds) < tolerance) break;
        s += ds;
        p = model_at(m, ply, q, s);
        hits = intersect_cylinder(o, z, p.p, normalize(p.d), p.ply_radius, enter, leave);
        if (!hits) break;
        lambda = clamp(enter, 0.0f, approach);
        if (std::fabs(ds) < tolerance) break;
    }
    const float v = (s - q.s0) * q.inv_h;
    trusted = v > -0.25f && v < 1.25f;
    if (!trusted) {  // back to the crossing's piece, rebuilt (rare) rather than copied (every entry)
        s = crossing;
        if (q.piece != start_piece) m.ply(ply, start_piece, q);
    }
    const Vec3 axis = normalize(p.d);
    Vec3 radial = z * lambda - p.p;
    radial -= axis * dot(radial, axis);
    const float len = length(radial);
    cos_incidence = len > 1e-12f ? std::fabs(radial.z) / len : 1.0f;
    return lambda;
}

// The circular method for one ply: the ray projected into the perpendicular cross-section at
// the tube hit, against the ply's circle there. `enter` is the matching distance along the 3D
// ray; false when the projected ray misses the circle.
bool circular_cut_hit(const YarnTubeHit& hit, const CentrelineProjection& at, const PlyCentre& centre, float& enter,
                      Vec3& normal) {
    const Vec3 tangent = at.point.tangent;
    Vec3 flat = hit.direction - tangent * dot(hit.direction, tangent);
    const float flat_length = length(flat);
    if (flat_length < 1e-4f) return false;
    flat = flat / flat_length;
    const Vec3 x0 = hit.point - tangent * dot(hit.point - at.point.position, tangent);
    const Vec3 w = x0 - centre.position;
    const float b = dot(w, flat), c = dot(w, w) - sqr(centre.radius);
    const float disc = b * b - c;
    if (disc < 0) return false;
    const float root = std::sqrt(disc);
    if (-b + root <= 0) return false;
    const float along = std::max(-b - root, 0.0f);
    enter = along / flat_length;
    normal = normalize(w + flat * along);
    return true;
}

PlyCut cut_at_hit(const CentrelineProjection& at, const YarnDescription& d, const YarnTwist& tw, int ply) {
    PlyCut cut;
    cut.g = at.segment + double(at.t);
    cut.segment = at.segment;
    cut.t = at.t;
    cut.yarn = at.point;
    cut.centre = ply_centre(at.point, d, tw, ply);
    return cut;
}

PlyHit trace_circular(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw,
                      const YarnTubeHit& hit, const CentrelineProjection& at) {
    Candidate best;
    bool found = false;
    int crossed = 0;
    Vec3 best_normal;
    for (int ply = 0; ply < d.plies(); ++ply) {
        const PlyCut cut = cut_at_hit(at, d, tw, ply);
        float enter;
        Vec3 normal;
        if (!circular_cut_hit(hit, at, cut.centre, enter, normal)) continue;
        ++crossed;
        if (found && enter >= best.enter) continue;
        found = true;
        best.ply = ply;
        best.cut = cut;
        best.enter = enter;
        best_normal = normal;
    }
    if (!found) return pass_through(frames, hit, at);
    PlyHit h = finish_hit(best, hit.point + hit.direction * best.enter, tw, hit);
    // The circular method's normal is the 2D one, in the frozen cross-section.
    h.normal = best_normal;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.plies_crossed = crossed;
    return h;
}

float closest_point_step(const PlyCut& cut, Vec3 x) {
    return closest_point_step(cut.centre.position, cut.centre.derivative, cut.centre.second_derivative, x);
}

// Distance from the ray point at `lambda` to the ply surface (negative inside), with `cut`
// moved to the helix point closest to it. Measured to that helix point itself, not to the
// line along its tangent: if the steps stop short of the closest point, the distance is still
// an upper bound, so a point outside the ply is never taken for one inside.
float helix_gap(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                int ply, float lambda, PlyCut& cut, int& evaluations) {
    const Vec3 x = hit.point + hit.direction * lambda;
    for (int step = 0; step < 6; ++step) {
        const float ds = closest_point_step(cut, x);
        cut = cut_at(frames, d, tw, ply, cut.g + ds / std::max(cut.yarn.speed, 1e-30f));
        ++evaluations;
        if (std::fabs(ds) < 1e-4f * cut.centre.radius) break;
    }
    return length(x - cut.centre.position) - cut.centre.radius;
}

// Where the ray enters the ply around one closest approach: the entry into the cut's
// cylinder, moved a few times to the cylinder at the helix point closest to it. If that does
// not settle (the ray runs nearly along the ply), a bracketed search on the distance to the
// helix between the tube entry and the closest approach. False when the ray misses the ply.
bool enter_ply(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
               bool exact_approach, float tolerance, int refinements, float max_shift, Candidate& cand,
               int& evaluations) {
    PlyCut cut = cand.cut;
    const float lambda_max = exact_approach ? std::max(cand.approach, 0.0f) : 1e30f;
    bool hits = intersect_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                   cut.centre.radius, cand.enter, cand.leave);
    if (!hits && !exact_approach) return false;
    float lambda = hits ? clamp(cand.enter, 0.0f, lambda_max) : lambda_max;
    for (int r = 0; r < refinements; ++r) {
        const Vec3 x = hit.point + hit.direction * lambda;
        const float ds = clamp(closest_point_step(cut, x), -max_shift, max_shift);
        if (hits && std::fabs(ds) < tolerance) {  // settled: this cut's cylinder is the answer
            cand.cut = cut;
            cand.enter = lambda;
            return true;
        }
        cut = cut_at(frames, d, tw, cand.ply, cut.g + ds / std::max(cut.yarn.speed, 1e-30f));
        ++evaluations;
        hits = intersect_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                  cut.centre.radius, cand.enter, cand.leave);
        if (!hits) break;
        lambda = clamp(cand.enter, 0.0f, lambda_max);
        if (std::fabs(ds) < tolerance) {
            cand.cut = cut;
            cand.enter = lambda;
            return true;
        }
    }
    if (!exact_approach) {  // the yarn-plane variant has no bracket: keep the last cylinder
        cand.cut = cut;
        cand.enter = lambda;
        return hits;
    }
    // Bracket: outside at the tube entry (else the ray starts in the ply), inside at the approach.
    cut = cand.cut;
    float lo = 0, hi = lambda_max;
    PlyCut lo_cut = cut, hi_cut = cut;
    float h_lo = helix_gap(frames, d, tw, hit, cand.ply, lo, lo_cut, evaluations);
    if (h_lo <= 0) {
        cand.cut = lo_cut;
        cand.enter = 0;
        return true;
    }
    float h_hi = helix_gap(frames, d, tw, hit, cand.ply, hi, hi_cut, evaluations);
    if (h_hi > kGraze * tolerance) return false;
    if (h_hi > 0) {  // a graze within the explicit reference's tolerance: touching at the approach
        cand.cut = hi_cut;
        cand.enter = hi;
        return true;
    }
    for (int step = 0; step < 30 && hi - lo > tolerance; ++step) {
        float mid = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);
        if (!(mid > lo + 0.05f * (hi - lo) && mid < hi - 0.05f * (hi - lo))) mid = 0.5f * (lo + hi);
        PlyCut mid_cut = h_hi > -h_lo ? lo_cut : hi_cut;
        const float h = helix_gap(frames, d, tw, hit, cand.ply, mid, mid_cut, evaluations);
        if (h > 0) lo = mid, h_lo = h, lo_cut = mid_cut;
        else hi = mid, h_hi = h, hi_cut = mid_cut;
    }
    cand.cut = hi_cut;
    cand.enter = hi;
    return true;
}

// Exact Newton steps on f = (P - x0)_perp . P'_perp (the ply-plane crossing) from g, inside the
// model's bracket [g_lo, g_hi]: settles a model crossing whose miss distance is too close to
// the ply radius for the model to decide. False when a step leaves the bracket or the steps
// run out.
bool exact_crossing(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                    int ply, double g, double g_lo, double g_hi, float tolerance, int max_steps, PlyCut& cut,
                    int& evaluations) {
    auto across = [&](Vec3 v) { return v - hit.direction * dot(v, hit.direction); };
    cut = cut_at(frames, d, tw, ply, g);
    ++evaluations;
    for (int step = 0; step < max_steps; ++step) {
        const PlyCentre& p = cut.centre;
        const Vec3 w = across(p.position - hit.point), d1 = across(p.derivative), d2 = across(p.second_derivative);
        const float f = dot(w, d1), slope = dot(d1, d1) + dot(w, d2);
        if (!(slope > 0)) return false;
        const float ds = -f / slope;  // m of yarn
        if (std::fabs(ds) < tolerance) return true;
        const double next = cut.g + ds / std::max(cut.yarn.speed, 1e-30f);
        if (!(next >= std::min(g_lo, g_hi) && next <= std::max(g_lo, g_hi))) return false;
        cut = cut_at(frames, d, tw, ply, next);
        ++evaluations;
    }
    return false;
}

// The stretch of yarn the ray crosses: entry to exit of the straight tube at the hit (on bends
// the real exit), widened by how far along the yarn a ply's cut can reach; clipped to open
// yarns' ends. Curve parameters and arc lengths from the hit's cross-section.
struct Stretch {
    double g_lo, g_hi;
    float s_lo, s_hi;
    float exit_distance;  // on bends, where the ray leaves the tube (m from the entry); else -1
};

Stretch ray_stretch(const CachedCurve& frames, const YarnDescription& d, const YarnTubeHit& hit,
                    const CentrelineProjection& at, float tan_psi) {
    const CurvePoint& c = at.point;
    const float radius = c.radius;
    const Vec3 w = hit.point - c.position;
    const Vec3 w_perp = w - c.tangent * dot(w, c.tangent);
    const Vec3 d_perp = hit.direction - c.tangent * dot(hit.direction, c.tangent);
    const float a = dot(d_perp, d_perp), b = dot(w_perp, d_perp);
    const float chord =
        (-b + std::sqrt(std::max(b * b - a * std::min(dot(w_perp, w_perp) - radius * radius, 0.0f), 0.0f))) / a;
    const float along = dot(hit.direction, c.tangent);
    const float margin = d.ply_radius * radius * (1 + tan_psi) + 0.05f * radius + 0.1f * chord * std::fabs(along);
    Stretch st;
    st.exit_distance = -1;
    st.s_lo = std::min(0.0f, chord * along) - margin;
    st.s_hi = std::max(0.0f, chord * along) + margin;
    const double g0 = at.segment + double(at.t), inv_speed = 1.0 / std::max(c.speed, 1e-30f);
    st.g_lo = g0 + st.s_lo * inv_speed;
    st.g_hi = g0 + st.s_hi * inv_speed;
    if (length(c.curvature) * radius > 0.02f) {
        // On a bend the straight tube's chord is only a guess: find where the ray really leaves.
        const TubeExit exit = tube_exit(frames, at, hit.point, hit.direction);
        st.exit_distance = exit.distance;  // a pass-through needs it again
        double g_exit = exit.segment + double(exit.t);
        if (frames.closed()) {
            // remainder(d, n), without the library call when |d| <= n / 2 (where it is d).
            const double n = frames.segment_count(), d = g_exit - g0;
            g_exit = g0 + (std::fabs(d) <= 0.5 * n ? d : std::remainder(d, n));
        }
        const double pad = margin * inv_speed;
        st.g_lo = std::min(st.g_lo, std::min(g0, g_exit) - pad);
        st.g_hi = std::max(st.g_hi, std::max(g0, g_exit) + pad);
    }
    if (!frames.closed()) {  // open yarns end: no plies beyond them
        st.g_lo = std::max(st.g_lo, 0.0);
        st.g_hi = std::min(st.g_hi, double(frames.segment_count()));
    }
    st.s_lo = static_cast<float>((st.g_lo - g0) * c.speed);
    st.s_hi = static_cast<float>((st.g_hi - g0) * c.speed);
    return st;
}

// The model-side search of one query: pieces built lazily, in the order the ray meets them,
// each scanned for every ply's crossings; a search that has every ply crossed and an entry no
// later piece can beat stops early.
class ModelSearch {
public:
    ModelSearch(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                const Stretch& stretch, float radius, const PlyTraceOptions& options)
        : frames_(frames), d_(d), stretch_(stretch), options_(options),
          ply_plane_(options.cross_section == PlyCrossSection::elliptical), search_(ply_plane_) {
        m_.origin = hit.point;
        m_.ez = hit.direction;
        m_.distance = d.ply_distance;
        m_.ply_radius = d.ply_radius;
        m_.rate = tw.ply_rate;
        m_.plies = std::min(std::max(1, d.plies()), kMaxPlies);
        m_.cos_offset = ply_offsets().cos[m_.plies];
        m_.sin_offset = ply_offsets().sin[m_.plies];
        // Pieces of at most model_turn radians of ply turn and model_length yarn radii.
        const float per_piece = std::min(options.model_turn / std::max(std::fabs(tw.ply_rate), 1e-30f),
                                         options.model_length * radius);
        m_.pieces = std::min(kMaxPieces, 1 + static_cast<int>((stretch.s_hi - stretch.s_lo) / per_piece));
        tolerance_ = options.tolerance * radius;
        slack_ = options.model_margin * radius + tolerance_;
        shift_ = stretch.s_hi - stretch.s_lo;
        search_.polys = &polys_;
        // Every ply's offset, padded to the grid's width with ply 0's.
        for (int i = 0; i < kMaxPlies; ++i) {
            grid_cos_[i] = m_.cos_offset[i < m_.plies ? i : 0];
            grid_sin_[i] = m_.sin_offset[i < m_.plies ? i : 0];
        }
        for (bool& h : have_) h = false;
    }

    // x: across the ray and the yarn (the cutting plane's normal); forward: the ray runs toward
    // larger arc length.
    void run(Vec3 x, bool forward) {
        forward_ = forward;
        m_.ex = x;
        m_.ey = cross(m_.ez, m_.ex);
        for (int n = 0; n < m_.pieces; ++n)
            if (!scan_piece(forward ? n : m_.pieces - 1 - n)) break;
    }

    const LocalYarn& model() const { return m_; }
    bool ply_plane() const { return ply_plane_; }
    float tolerance() const { return tolerance_; }
    float shift() const { return shift_; }
    int evaluations = 0;  // exact frames evaluated for the knots
    Slots<ModelCandidate, kMaxWork> candidates;
    int count = 0;
    uint32_t unconverged_mask = 0;
    uint32_t sure_mask = 0;  // plies crossed by the model's margin

private:
    // The exact frame at knot j (evenly spaced in curve parameter over the stretch).
    const Knot& knot(int j) {
        if (have_[j]) return knots_[j];
        const double g = stretch_.g_lo + (stretch_.g_hi - stretch_.g_lo) * j / m_.pieces;
        uint32_t segment;
        float t;
        locate(frames_, g, segment, t);
        const CurvePoint k = frames_.evaluate(segment, t);
        ++evaluations;
        if (!origin_set_) s_origin_ = k.arc_length, origin_set_ = true;
        // Arc length continuous across a loop's seam, from an evaluated neighbour.
        float s = k.arc_length - s_origin_;
        const float total = frames_.frames().total_length();
        if (frames_.closed() && j > 0 && have_[j - 1])
            while (s < knots_[j - 1].s) s += total;
        else if (frames_.closed() && j < m_.pieces && have_[j + 1])
            while (s > knots_[j + 1].s) s -= total;
        make_knot(k, g, s, m_, knots_[j]);
        have_[j] = true;
        return knots_[j];
    }

    // Builds piece j and finds its crossings; false when no later piece can matter.
    bool scan_piece(int j) {
        make_piece(knot(j), knot(j + 1), m_, m_.piece[j]);
        m_.built_lo = std::min(m_.built_lo, j);
        m_.built_hi = std::max(m_.built_hi, j);
        const Piece& q = m_.piece[j];
        // No entry into a ply near a helix point of this piece comes before this ray distance:
        // the helix stays within a ply distance of the centre-line, which bulges at most
        // h^2 kappa / 8.
        const float a_max = d_.ply_distance * std::max(q.r0, q.r1), r_max = d_.ply_radius * std::max(q.r0, q.r1);
        const float earliest = std::min(knots_[j].c.z, knots_[j + 1].c.z) - 1.25f * q.h * q.h * q.kappa / 8 -
                               a_max - r_max - slack_;
        // Late: entries near this piece cannot win. A ply still within reach where the previous
        // piece ended may enter back there, so it is not late; the others only matter for N_i.
        const uint32_t late = ply_plane_ && earliest > best_bound_ ? ~continuing_ : 0u;
        const uint32_t all = (1u << m_.plies) - 1;
        if ((late & all) == all && sure_mask == all) return false;
        polys_.reset(m_, j);
        piece_bounds(m_, q, search_);
        search_.reach2 = sqr(r_max + slack_);
        search_.count = 0;
        scan_grid(q, late, sqr(std::max(d_.ply_radius * std::min(q.r0, q.r1) - slack_, 0.0f)));
        const int first = count;
        for (int w = 0; w < search_.count && count < kMaxWork; ++w) add_crossing(search_.work[w], j);
        if (ply_plane_) add_entries(first, late);
        return true;
    }

    // Every ply at the piece's grid nodes; intervals that may hold a crossing become work. Also
    // notes which plies are within reach where the next piece in ray order begins.
    void scan_grid(const Piece& q, uint32_t late, float sure2) {
        grid_.set(q, grid_cos_, grid_sin_, m_.plies);
        float s_prev = q.s0;
        int prev = 0;
        grid_.node(m_.plies, 0, q.inv_h, ply_plane_, prev);
        uint32_t start_reach = 0;
        for (int i = 0; i < m_.plies; ++i) start_reach |= uint32_t(grid_.D[prev][i] <= search_.reach2) << i;
        for (int k = 1; k <= kSubsteps; ++k) {
            const int next = prev ^ 1;
            const float s_next = q.s0 + q.h * k / kSubsteps;
            grid_.node(m_.plies, float(k) / kSubsteps, q.inv_h, ply_plane_, next);
            const float *D0 = grid_.D[prev], *f0 = grid_.f[prev], *slope0 = grid_.slope[prev];
            const float *D1 = grid_.D[next], *f1 = grid_.f[next], *slope1 = grid_.slope[next];
            for (int i = 0; i < m_.plies; ++i) {
                if (ply_plane_ &&
                    out_of_reach(s_prev, D0[i], s_next, D1[i], search_.reach2, search_.speed, search_.accel))
                    continue;
                if (late >> i & 1) {
                    if (sure_mask >> i & 1) continue;
                    // A closest approach bracketed with an end this close to the ray: crossed,
                    // without solving for where.
                    if (f0[i] < 0 && f1[i] >= 0 && std::min(D0[i], D1[i]) < sure2) {
                        sure_mask |= 1u << i;
                        continue;
                    }
                }
                search_.interval(i, {s_prev, D0[i], f0[i], slope0[i]}, {s_next, D1[i], f1[i], slope1[i]}, 0);
            }
            s_prev = s_next;
            prev = next;
        }
        uint32_t end_reach = 0;
        for (int i = 0; i < m_.plies; ++i) end_reach |= uint32_t(grid_.D[prev][i] <= search_.reach2) << i;
        continuing_ = forward_ ? end_reach : start_reach;
    }

    // One bracketed crossing solved on the model; the ply plane keeps it if within reach.
    void add_crossing(const Work& wk, int j) {
        ModelCandidate mc;
        mc.ply = wk.ply;
        mc.piece = j;
        mc.s_lo = wk.lo.s;
        mc.s_hi = wk.hi.s;
        if (!solve(polys_[wk.ply], wk, ply_plane_, tolerance_, options_.max_iterations, mc.s_cross)) {
            unconverged_mask |= 1u << wk.ply;
            return;
        }
        const ModelPoint p = polys_[wk.ply].at(mc.s_cross);
        mc.approach = p.p.z;
        mc.s_enter = mc.s_cross;
        mc.piece_enter = j;
        mc.enter = ply_plane_ ? kNoEntry : 0;  // the ply plane's entries come later, where they matter
        mc.slack = 0;
        mc.ambiguous = false;
        mc.miss = 0;
        if (ply_plane_) {
            const float miss = std::sqrt(p.p.x * p.p.x + p.p.y * p.p.y);
            if (miss > p.ply_radius + slack_) return;  // passes beside the ply
            mc.ambiguous = miss > p.ply_radius - slack_;
            mc.miss = miss - p.ply_radius;
            if (!mc.ambiguous) sure_mask |= 1u << wk.ply;
        }
        candidates[count++] = mc;
    }

    // Model entries of the candidates from `first` on, except those of late plies.
    void add_entries(int first, uint32_t late) {
        for (int i = first; i < count; ++i) {
            ModelCandidate& mc = candidates[i];
            if (late >> mc.ply & 1) continue;
            float cos_incidence;
            bool trusted;
            PlyPoly at_entry = polys_[mc.ply];
            mc.enter = model_entry(m_, mc.ply, at_entry, std::max(mc.approach, 0.0f), tolerance_,
                                   options_.refinements, shift_, mc.s_enter, cos_incidence, trusted);
            mc.piece_enter = at_entry.piece;
            // An entry the model cannot vouch for is refined whatever its estimate.
            mc.slack = trusted ? slack_ / std::max(cos_incidence, 0.05f) + tolerance_ : kNoEntry;
            if (!mc.ambiguous) best_bound_ = std::min(best_bound_, mc.enter + mc.slack);
        }
    }

    static constexpr float kNoEntry = 1e30f;
    const CachedCurve& frames_;
    const YarnDescription& d_;
    const Stretch& stretch_;
    const PlyTraceOptions& options_;
    bool ply_plane_;
    float tolerance_ = 0, slack_ = 0, shift_ = 0;
    LocalYarn m_;
    Slots<Knot, kMaxPieces + 1> knots_;
    bool have_[kMaxPieces + 1];
    float s_origin_ = 0;
    bool origin_set_ = false;
    Search search_;
    PiecePlies polys_;
    float grid_cos_[kMaxPlies], grid_sin_[kMaxPlies];
    PieceGrid grid_;  // left uninitialized: filled per piece
    float best_bound_ = kNoEntry;  // no exact entry can come later than this
    bool forward_ = true;
    uint32_t continuing_ = 0;  // plies within reach where the next piece in ray order begins
};

// `frames` caches the few segments the ray's stretch spans (expanded once for the projection,
// the knots and the exact refinements); `at` is the projection of the tube entry, without its
// frame (only the circular fallback needs that).
PlyHit trace_elliptical(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw,
                        const YarnTubeHit& hit, const CentrelineProjection& at, const PlyTraceOptions& options) {
    const CurvePoint& c = at.point;
    const Vec3 across = cross(c.tangent, hit.direction);
    const float across_length = length(across);
    if (across_length < 1e-4f) return pass_through(frames, hit, at);
    const float radius = c.radius;
    const float along = dot(hit.direction, c.tangent);
    const Stretch stretch = ray_stretch(frames, d, hit, at, std::fabs(along) / across_length);
    if (!(stretch.s_hi - stretch.s_lo > 1e-6f * radius))
        return stretch.exit_distance >= 0 ? pass_through(hit, stretch.exit_distance) : pass_through(frames, hit, at);

    ModelSearch search(frames, d, tw, hit, stretch, radius, options);
    search.run(normalize(cross(hit.direction, across / across_length)), along >= 0);
    const LocalYarn& m = search.model();
    const bool ply_plane = search.ply_plane();
    const float tolerance = search.tolerance();
    int evaluations = search.evaluations;

    // Exact work: ambiguous misses settled on the curve, then entries refined in the order of
    // the model's, until the next model entry (less its slack) is past the best exact one.
    uint32_t crossed_mask = ply_plane ? search.sure_mask : 0;
    int order[kMaxWork];
    int kept = 0;
    for (int i = 0; i < search.count; ++i) {
        ModelCandidate& mc = search.candidates[i];
        if (mc.ambiguous) {
            PlyCut cut;
            mc.ambiguous = exact_crossing(frames, d, tw, hit, mc.ply, m.g(mc.piece, mc.s_cross),
                                          m.g(mc.piece, mc.s_lo), m.g(mc.piece, mc.s_hi), tolerance,
                                          std::max(options.max_iterations, 1), cut, evaluations);
            if (mc.ambiguous) {  // settled: the exact miss decides, and a graze needs the exact approach
                const Vec3 w = cut.centre.position - hit.point;
                mc.approach = dot(w, hit.direction);
                if (length(w - hit.direction * mc.approach) > cut.centre.radius + kGraze * tolerance) continue;
            } else if (mc.miss > 0) {
                continue;  // not settled: the model's own miss decides
            }
        }
        if (ply_plane) crossed_mask |= 1u << mc.ply;
        int k = kept++;  // insertion by entry less slack
        for (; k > 0 && search.candidates[order[k - 1]].enter - search.candidates[order[k - 1]].slack >
                            mc.enter - mc.slack;
             --k)
            order[k] = order[k - 1];
        order[k] = i;
    }
    Candidate best;
    bool found = false;
    int worst = 0;
    for (int n = 0; n < kept; ++n) {
        const ModelCandidate& mc = search.candidates[order[n]];
        if (ply_plane && found && mc.enter - mc.slack >= best.enter) break;
        // From the model's helix point nearest the entry: usually within tolerance already.
        int spent = 1;
        Candidate cand{mc.ply, cut_at(frames, d, tw, mc.ply, m.g(mc.piece_enter, mc.s_enter))};
        cand.approach = mc.approach;
        if (enter_ply(frames, d, tw, hit, ply_plane, tolerance, options.refinements, search.shift(), cand, spent)) {
            if (!ply_plane) crossed_mask |= 1u << cand.ply;
            if (!found || cand.enter < best.enter) best = cand;
            found = true;
        }
        evaluations += spent;
        worst = std::max(worst, spent);
    }

    // Fallback: a ply whose crossing did not converge is taken as the circular method sees it,
    // at the tube hit's cross-section (with the frame there, which `at` lacks).
    if (search.unconverged_mask != 0) {
        CentrelineProjection framed = at;
        framed.point = frames.evaluate(at.segment, at.t);
        for (int ply = 0; ply < m.plies; ++ply) {
            if (!(search.unconverged_mask >> ply & 1)) continue;
            Candidate cand{ply, cut_at_hit(framed, d, tw, ply)};
            Vec3 normal;
            if (!circular_cut_hit(hit, framed, cand.cut.centre, cand.enter, normal)) continue;
            crossed_mask |= 1u << ply;
            if (!found || cand.enter < best.enter) best = cand;
            found = true;
        }
    }

    PlyHit h = found ? finish_hit(best, hit.point + hit.direction * std::max(best.enter, 0.0f), tw, hit)
                     : stretch.exit_distance >= 0 ? pass_through(hit, stretch.exit_distance)
                                                  : pass_through(frames, hit, at);
    if (found) h.plies_crossed = __builtin_popcount(crossed_mask);
    h.iterations = evaluations;
    h.max_ply_iterations = worst;
    h.converged = search.unconverged_mask == 0;
    return h;
}

// ---- Local method: the yarn straightened, to second order, at the hit ---------------------
// Near the hit's cross-section (arc length s from it) the centre-line is c + T s + kappa s^2 / 2
// and the rotation-minimizing frame turns as N(s) = N - (N.kappa) s T (likewise B), so ply i is
// an analytic helix in s with phase phi_i + rate s: crossings and entries need only sines, no
// curve evaluation. Exact on straight yarns; on bends the error grows as |kappa|^2 s^3, i.e.
// with the stretch an oblique ray crosses (docs/implicit-geometry.md has the measurements).

// cos and sin to ~3e-7 for |a| up to ~1e4 (every query evaluates dozens of phases; libm's
// sincosf was a quarter of the local method's time): a less q quarter turns (q: a rounded to
// whole quarter turns, the reduction by pi/2 in two parts), by Taylor polynomials on
// [-pi/4, pi/4]; the caller turns them by q.
inline void reduced_sincos(float a, float q, float& sr, float& cr) {
    const float r = (a - q * 1.57079625f) - q * 7.54978995e-8f;
    const float r2 = r * r;
    sr = r * (1 + r2 * (-1.0f / 6 + r2 * (1.0f / 120 + r2 * (-1.0f / 5040))));
    cr = 1 + r2 * (-0.5f + r2 * (1.0f / 24 + r2 * (-1.0f / 720 + r2 * (1.0f / 40320))));
}

// nearbyint without a library call: adding and removing 1.5 * 2^23 rounds to the nearest whole
// number (ties to even, as nearbyint in the default rounding mode) for |x| < 2^22.
inline float quarter_turns(float a) { return (a * 0.636619772f + 12582912.0f) - 12582912.0f; }

inline void turn_sincos(float a, float& c, float& s) {
    const float x = a * 0.636619772f;
    const float q = std::fabs(x) < 4194304.0f ? quarter_turns(a) : std::nearbyint(x);
    float sr, cr;
    reduced_sincos(a, q, sr, cr);
    switch (static_cast<int>(q) & 3) {
        case 0: c = cr, s = sr; break;
        case 1: c = -sr, s = cr; break;
        case 2: c = -cr, s = -sr; break;
        default: c = sr, s = -cr; break;
    }
}

struct LocalHelices {
    Vec3 c, tangent, kappa, normal, binormal;  // at the hit's cross-section; c relative to the tube entry
    Vec3 ray;                                  // unit ray direction
    float nk = 0, bk = 0;                      // N.kappa, B.kappa
    float offset = 0, ply_radius = 0, rate = 0, phase = 0;  // ply distance (m), radius (m), rad/m, ply 0 at s = 0
    // The same seen along the ray, in coordinates across it (normal and binormal times the ply
    // distance): all a scan node needs, at two thirds of the work.
    Vec2 c_across, tangent_across, kappa_across, normal_across, binormal_across;
    void set_across(Vec3 u) {
        const Vec3 v = cross(ray, u);
        const auto across = [&](Vec3 x) { return Vec2(dot(x, u), dot(x, v)); };
        c_across = across(c), tangent_across = across(tangent), kappa_across = across(kappa);
        normal_across = across(normal * offset), binormal_across = across(binormal * offset);
    }

    // Ply centre relative to the tube entry (w), its derivatives in s (w1, w2), given the cosine
    // and sine of the ply's phase at s.
    void at(float s, float cp, float sp, Vec3& w, Vec3& w1, Vec3* w2) const {
        const Vec3 out = normal * cp + binormal * sp, around = binormal * cp - normal * sp;
        const float lean = 1 - offset * (nk * cp + bk * sp), turn = offset * rate * (bk * cp - nk * sp);
        w = c + kappa * (0.5f * s * s) + out * offset + tangent * (s * lean);
        w1 = kappa * s + around * (offset * rate) + tangent * (lean - s * turn);
        if (w2) *w2 = kappa - out * (offset * rate * rate) - tangent * (2 * turn);
    }
    // Across-the-ray parts: the ply-plane crossing condition f = w_perp . w1_perp and its slope.
    float crossing(const Vec3& w, const Vec3& w1, const Vec3* w2 = nullptr, float* slope = nullptr) const {
        const float wz = dot(w, ray), w1z = dot(w1, ray);
        if (slope) *slope = dot(w1, w1) - w1z * w1z + dot(w, *w2) - wz * dot(*w2, ray);
        return dot(w, w1) - wz * w1z;
    }
    float miss2(const Vec3& w) const {
        const float wz = dot(w, ray);
        return dot(w, w) - wz * wz;
    }
    float offsets[kMaxPlies];  // 2 pi i / N of ply i, set by set_offsets
    void set_offsets(int plies) {
        for (int i = 0; i < kMaxPlies; ++i) offsets[i] = i < plies ? 2 * kPi * i / plies : 0.0f;
    }
    void phase_at(int ply, int plies, float s, float& cp, float& sp) const {
        turn_sincos(phase + rate * s + offsets[ply], cp, sp);
    }
};

// The crossing in [lo, hi] (f(lo) < 0 <= f(hi)): Newton steps kept inside the bracket. w and
// w1 there: once converged, the last evaluation's carried over the last step to first order.
float local_crossing(const LocalHelices& m, int ply, int plies, float lo, float hi, float f_lo, float f_hi,
                     float tolerance, Vec3& w, Vec3& w1) {
    float s = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    for (int step = 0; step < 8; ++step) {
        float cp, sp, slope;
        Vec3 w2;
        m.phase_at(ply, plies, s, cp, sp);
        m.at(s, cp, sp, w, w1, &w2);
        const float f = m.crossing(w, w1, &w2, &slope);
        if (f < 0) lo = s;
        else hi = s;
        float next = slope > 0 ? s - f / slope : 0.5f * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
        const float ds = next - s;
        s = next;
        if (std::fabs(ds) < tolerance) {
            w += w1 * ds;
            w1 += w2 * ds;
            return s;
        }
    }
    float cp, sp;
    m.phase_at(ply, plies, s, cp, sp);
    m.at(s, cp, sp, w, w1, nullptr);
    return s;
}

// Distance from the ray point at `lambda` to ply `ply`'s surface (negative inside), with s
// moved to the helix point closest to it; to the point itself, an upper bound if the steps
// stop short (as helix_gap).
float local_gap(const LocalHelices& m, int ply, int plies, float lambda, float max_shift, float& s) {
    const Vec3 x = m.ray * lambda;
    Vec3 w, w1, w2;
    for (int step = 0; step < 6; ++step) {
        float cp, sp;
        m.phase_at(ply, plies, s, cp, sp);
        m.at(s, cp, sp, w, w1, &w2);
        const Vec3 r = w - x;
        const float slope = dot(w1, w1) + dot(r, w2);
        const float ds = slope > 0 ? -dot(r, w1) / slope : 0.0f;
        if (std::fabs(ds) < 1e-5f * max_shift) break;
        s += clamp(ds, -max_shift, max_shift);
    }
    return length(x - w) - m.ply_radius;
}

// Where the ray (from the tube entry) enters ply `ply` near its crossing at s, whose closest
// approach lies at ray distance `approach`: the entry into the cylinder along the helix there,
// moved to the helix point closest to that entry. When that does not settle (a ray almost
// along the ply), regula falsi on the distance to the helix between the tube entry and the
// approach. False when the ray misses the ply.
bool local_entry(const LocalHelices& m, int ply, int plies, float tolerance, float max_shift, float approach,
                 float& s, float& enter) {
    const float s_crossing = s;
    for (int step = 0; step < 6; ++step) {
        float cp, sp, leave;
        Vec3 w, w1, w2;
        m.phase_at(ply, plies, s, cp, sp);
        m.at(s, cp, sp, w, w1, &w2);
        if (!intersect_cylinder(Vec3(0.0f), m.ray, w, normalize(w1), m.ply_radius, enter, leave)) break;
        const Vec3 r = w - m.ray * std::max(enter, 0.0f);  // ply centre minus the entry point
        const float slope = dot(w1, w1) + dot(r, w2);
        const float ds = slope > 0 ? -dot(r, w1) / slope : 0.0f;
        if (std::fabs(ds) < tolerance) return true;
        s += clamp(ds, -max_shift, max_shift);
    }
    // Bracket: outside at the tube entry (else the ray starts inside the ply), inside at the approach.
    float lo = 0, hi = std::max(approach, 0.0f), s_lo = s_crossing, s_hi = s_crossing;
    float g_lo = local_gap(m, ply, plies, lo, max_shift, s_lo);
    if (g_lo <= 0) {
        s = s_lo;
        enter = 0;
        return true;
    }
    float g_hi = local_gap(m, ply, plies, hi, max_shift, s_hi);
    if (g_hi > 0) return false;
    for (int step = 0; step < 30 && hi - lo > tolerance; ++step) {
        float mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        if (!(mid > lo + 0.05f * (hi - lo) && mid < hi - 0.05f * (hi - lo))) mid = 0.5f * (lo + hi);
        float s_mid = g_hi > -g_lo ? s_lo : s_hi;
        const float g = local_gap(m, ply, plies, mid, max_shift, s_mid);
        if (g > 0) lo = mid, g_lo = g, s_lo = s_mid;
        else hi = mid, g_hi = g, s_hi = s_mid;
    }
    s = s_hi;
    enter = hi;
    return true;
}

// The yarn's cross-section at s, from the local model (frame to first order, as the helices).
PlyCut local_cut(const CurveFrames& frames, const CentrelineProjection& at, const LocalHelices& m,
                 const YarnDescription& d, const YarnTwist& tw, int ply, float s, Vec3 entry) {
    PlyCut cut;
    const CurvePoint& c = at.point;
    cut.g = at.segment + double(at.t) + s / std::max(c.speed, 1e-30f);
    cut.segment = at.segment;
    cut.t = at.t;
    frames.advance(cut.segment, cut.t, s / std::max(c.speed, 1e-30f));
    cut.yarn = c;
    cut.yarn.position = entry + m.c + m.tangent * s + m.kappa * (0.5f * s * s);
    cut.yarn.tangent = normalize(m.tangent + m.kappa * s);
    cut.yarn.normal = m.normal - m.tangent * (m.nk * s);
    cut.yarn.binormal = m.binormal - m.tangent * (m.bk * s);
    cut.yarn.arc_length = c.arc_length + s;
    const float total = frames.total_length();
    if (frames.closed() && total > 0) cut.yarn.arc_length -= total * std::floor(cut.yarn.arc_length / total);
    // The phase continues from the hit (a loop's seam must not jump it): ply_centre takes the
    // arc length, so give it the unwrapped phase directly.
    const float phase = m.phase + m.rate * s + 2 * kPi * ply / std::max(1, d.plies());
    cut.centre = ply_centre(cut.yarn, d, tw, phase, std::cos(phase), std::sin(phase));
    return cut;
}

struct LocalNode {
    float s, f, miss, pace;  // arc length, crossing function, distance from the ray (m), |w1 across the ray|
};

// LocalHelices::at across the ray, from the cosine and sine of the ply's phase at s.
inline LocalNode node_at(const LocalHelices& m, float s, float cp, float sp) {
    const Vec2 out = m.normal_across * cp + m.binormal_across * sp;
    const Vec2 around = m.binormal_across * cp - m.normal_across * sp;
    const float lean = 1 - m.offset * (m.nk * cp + m.bk * sp), turn = m.offset * m.rate * (m.bk * cp - m.nk * sp);
    const Vec2 w = m.c_across + m.kappa_across * (0.5f * s * s) + out + m.tangent_across * (s * lean);
    const Vec2 w1 = m.kappa_across * s + around * m.rate + m.tangent_across * (lean - s * turn);
    return {s, dot(w, w1), length(w), length(w1)};
}

// Out of line (scan subdivisions and huge phases only): inlined, it grew the scan past what
// GCC inlines into trace_local, +3 % instructions.
[[gnu::noinline]] LocalNode local_node(const LocalHelices& m, int ply, int plies, float s) {
    float cp, sp;
    m.phase_at(ply, plies, s, cp, sp);
    return node_at(m, s, cp, sp);
}

// Bounds over a query's stretch on the derivatives of a ply centre seen across the ray
// (m per m of s to the k-th power): |w1|, |w2|, |w3|, |w4|.
struct HelixBounds {
    float speed, bend, jerk, snap;
};

// The least the squared miss distance D = |w|^2 can be over [a, b]: the cubic Hermite
// interpolant of D from the ends' values and slopes (D' = 2 f) less its error bound,
// max |D4| (b - a)^4 / 384, with the fourth derivative D4 = 2 (3 |w2|^2 + 4 w1.w3 + w.w4)
// bounded from `far` (|w| over the interval), `fastest` (|w1|) and the helix bounds.
float least_miss2(const LocalNode& a, const LocalNode& b, float far, float fastest, const HelixBounds& bounds) {
    const float h = b.s - a.s;
    const float d0 = sqr(a.miss), d1 = sqr(b.miss), s0 = 2 * a.f * h, s1 = 2 * b.f * h;
    // D(a + t h) = d0 + s0 t + c2 t^2 + c3 t^3 on t in [0, 1]; its least value at an end or
    // at a root of the slope s0 + 2 c2 t + 3 c3 t^2.
    const float c2 = 3 * (d1 - d0) - 2 * s0 - s1, c3 = 2 * (d0 - d1) + s0 + s1;
    float least = std::min(d0, d1);
    const auto consider = [&](float t) {
        if (t > 0 && t < 1) least = std::min(least, d0 + t * (s0 + t * (c2 + t * c3)));
    };
    // The slope's roots by the cancellation-free form (a root off by rounding would
    // overstate the least value).
    const float disc = c2 * c2 - 3 * c3 * s0;
    if (disc >= 0) {
        const float q = -(c2 + std::copysign(std::sqrt(disc), c2));
        if (c3 != 0) consider(q / (3 * c3));
        if (q != 0) consider(s0 / q);
    }
    const float snap = 2 * (3 * sqr(bounds.bend) + 4 * fastest * bounds.jerk + far * bounds.snap);
    return least - snap * sqr(sqr(h)) / 384;
}

// The scan's grid nodes for every ply (node k of ply i at [k * kMaxPlies + i]), built in one
// pass over the plies per node that the compiler vectorises: local_node's arithmetic lane by
// lane. Phases too large for quarter_turns (|phase| >= 2^22 pi / 2) take local_node itself.
struct LocalGrid {
    static constexpr int kMaxNodes = 65;
    int steps = 0;  // intervals between the nodes
    Slots<float, kMaxNodes> s;
    Slots<float, kMaxNodes * kMaxPlies> f, miss, pace;

    void build(const LocalHelices& m, int plies, float s_lo, float s_hi, int intervals) {
        steps = intervals;
        const int lanes = (plies + 3) & ~3;
        const float h = (s_hi - s_lo) / steps;
        const bool fits =
            std::fabs(m.phase) + std::fabs(m.rate) * std::max(std::fabs(s_lo), std::fabs(s_hi)) + 2 * kPi < 6.5e6f;
        for (int k = 0; k <= steps; ++k) {
            const float at = k == steps ? s_hi : s_lo + h * k;
            s[k] = at;
            if (fits) {
                nodes(m, lanes, at, &f[k * kMaxPlies], &miss[k * kMaxPlies], &pace[k * kMaxPlies]);
                continue;
            }
            for (int i = 0; i < plies; ++i) {
                const LocalNode n = local_node(m, i, plies, at);
                f[k * kMaxPlies + i] = n.f, miss[k * kMaxPlies + i] = n.miss, pace[k * kMaxPlies + i] = n.pace;
            }
        }
    }
    LocalNode node(int k, int ply) const {
        return {s[k], f[k * kMaxPlies + ply], miss[k * kMaxPlies + ply], pace[k * kMaxPlies + ply]};
    }

private:
    static void nodes(const LocalHelices& m, int lanes, float s, float* __restrict f, float* __restrict miss,
                      float* __restrict pace) {
        for (int i = 0; i < lanes; ++i) {
            const float a = m.phase + m.rate * s + m.offsets[i], q = quarter_turns(a);
            float sr, cr;
            reduced_sincos(a, q, sr, cr);
            // turn_sincos's quadrant by selects: a switch would keep the loop from vectorising.
            const int quadrant = static_cast<int>(q);
            const float cs = (quadrant & 1) ? sr : cr, sn = (quadrant & 1) ? cr : sr;
            const float cp = ((quadrant + 1) & 2) ? -cs : cs, sp = (quadrant & 2) ? -sn : sn;
            const LocalNode n = node_at(m, s, cp, sp);
            f[i] = n.f, miss[i] = n.miss, pace[i] = n.pace;
        }
    }
};

// Calls visit(s, w, w1) (ply centre relative to the tube entry, its derivative) for every
// closest approach of ply `ply` to the ray in [s_lo, s_hi] that may be within its radius, and
// for a stretch end where the ply is within reach moving away (start) or toward the ray (end).
// The ply's distance to the ray changes by at most `bounds.speed` per m of s and its second
// derivative is at most `bounds.bend`, which bounds f' = |w1_perp|^2 + w_perp.w2_perp: an
// interval is skipped when the ply cannot come within reach at a root of f or anywhere in it
// (least_miss2), solved when f changes sign, and split only when f's slope bounds leave room
// for a pair of roots to hide between the nodes.
template <class Visit>
void local_approaches(const LocalHelices& m, int ply, int plies, const LocalGrid& grid, const HelixBounds& bounds,
                      float tolerance, const Visit& visit) {
    const int steps = grid.steps;
    const float s_lo = grid.s[0], s_hi = grid.s[steps];
    const float speed_bound = bounds.speed, bend_bound = bounds.bend;
    const float reach2 = sqr(m.ply_radius + kGraze * tolerance);
    const float finest = 0.25f * m.ply_radius / speed_bound;
    const auto visit_end = [&](float s) {
        float cp, sp;
        Vec3 w, w1;
        m.phase_at(ply, plies, s, cp, sp);
        m.at(s, cp, sp, w, w1, nullptr);
        visit(s, w, w1);
    };
    LocalNode prev = grid.node(0, ply);
    if (prev.f >= 0 && prev.miss <= m.ply_radius) visit_end(s_lo);
    for (int k = 1; k <= steps; ++k) {
        const LocalNode next = grid.node(k, ply);
        LocalNode stack[24][2];
        int depth = 0;
        stack[depth][0] = prev, stack[depth++][1] = next;
        while (depth > 0) {
            const LocalNode a = stack[--depth][0], b = stack[depth][1];
            const float width = b.s - a.s;
            if (0.5f * (a.miss + b.miss - speed_bound * width) > m.ply_radius) continue;
            // f, the slope of miss^2 / 2, has its own slope f' in [-fall, rise].
            const float slowest = std::max(std::min(a.pace, b.pace) - 0.5f * bend_bound * width, 0.0f);
            const float fastest = std::max(a.pace, b.pace) + 0.5f * bend_bound * width;
            const float far = std::max(a.miss, b.miss) + 0.5f * speed_bound * width;
            const float fall = far * bend_bound - slowest * slowest, rise = far * bend_bound + fastest * fastest;
            // At a root x of f, miss^2 >= miss(a)^2 - rise (x - a)^2 (likewise from b): the
            // least such bound over the interval, where both agree, must be within visit's reach.
            if (rise > 0) {
                const float from_a =
                    clamp(0.5f * width + 0.5f * (sqr(a.miss) - sqr(b.miss)) / (rise * width), 0.0f, width);
                if (std::max(sqr(a.miss) - rise * sqr(from_a), sqr(b.miss) - rise * sqr(width - from_a)) > reach2)
                    continue;
            }
            // Nowhere within reach (with a margin for the bound's own rounding).
            if (least_miss2(a, b, far, fastest, bounds) > 1.001f * reach2) continue;
            if (a.f < 0 && b.f >= 0) {
                Vec3 w, w1;
                const float s = local_crossing(m, ply, plies, a.s, b.s, a.f, b.f, 10 * tolerance, w, w1);
                visit(s, w, w1);  // refined at the entry
                continue;
            }
            // A hidden rising root needs f to fall from a.f below zero or to b.f from above
            // it, and to rise from a.f or to b.f: skipped when the interval is too short for that.
            const float descent = std::max(a.f, 0.0f) + std::max(-b.f, 0.0f);
            const float ascent = std::max(-a.f, 0.0f) + std::max(b.f, 0.0f);
            if (fall < 0 || descent * rise + ascent * fall > width * fall * rise) continue;
            if (width < finest || depth + 2 > 24) continue;
            const LocalNode mid = local_node(m, ply, plies, 0.5f * (a.s + b.s));
            stack[depth][0] = mid, stack[depth++][1] = b;  // the nearer half is examined first
            stack[depth][0] = a, stack[depth++][1] = mid;
        }
        prev = next;
    }
    if (prev.f < 0 && prev.miss <= m.ply_radius) visit_end(s_hi);
}

// at_entry: `at` is the projection of the tube entry itself (else of a point near it), so a
// pass-through's exit search may start from it.
PlyHit trace_local(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                   const CentrelineProjection& at, const PlyTraceOptions& options, bool at_entry) {
    const auto pass = [&] { return at_entry ? pass_through(frames, hit, at) : pass_through(frames, hit, at.segment, at.t); };
    const CurvePoint& c = at.point;
    const float radius = std::max(c.radius, 1e-30f);
    const Vec3 across = cross(c.tangent, hit.direction);
    const float across_length = length(across);
    if (across_length < 1e-4f) return pass();

    LocalHelices m;
    m.c = c.position - hit.point;
    m.tangent = c.tangent;
    m.kappa = c.curvature;
    m.normal = c.normal;
    m.binormal = c.binormal;
    m.ray = hit.direction;
    m.nk = dot(c.normal, c.curvature);
    m.bk = dot(c.binormal, c.curvature);
    m.offset = d.ply_distance * radius;
    m.ply_radius = d.ply_radius * radius;
    m.rate = tw.ply_rate;
    m.phase = ply_phase(tw, c.arc_length);
    const int plies = std::max(1, d.plies());
    m.set_offsets(plies);
    m.set_across(across / across_length);

    // The stretch the ray crosses: the straight tube's chord from the entry (which may lie off
    // the modelled cross-section along the yarn), widened by how far a ply's cut reaches along
    // the yarn; clipped to an open yarn's ends.
    const float along = dot(hit.direction, c.tangent), entry_s = dot(-m.c, c.tangent);
    const Vec3 w_perp = -m.c - c.tangent * dot(-m.c, c.tangent);
    const Vec3 d_perp = hit.direction - c.tangent * along;
    const float a = dot(d_perp, d_perp), b = dot(w_perp, d_perp);
    const float chord = (-b + safe_sqrt(b * b - a * std::min(dot(w_perp, w_perp) - radius * radius, 0.0f))) / a;
    const float reach = m.ply_radius * (1 + std::fabs(along) / across_length) + 0.05f * radius +
                        0.1f * chord * std::fabs(along);
    float s_lo = entry_s + std::min(0.0f, chord * along) - reach;
    float s_hi = entry_s + std::max(0.0f, chord * along) + reach;
    if (!frames.closed()) {
        s_lo = std::max(s_lo, -c.arc_length);
        s_hi = std::min(s_hi, frames.total_length() - c.arc_length);
    }
    if (!(s_hi > s_lo)) return pass();

    // Nodes every quarter turn of the plies (at most 64), subdivided where the ply may come
    // within reach of the ray: a sign change of f brackets a closest approach.
    const float quarter = 0.5f * kPi / std::max(std::fabs(m.rate), 1e-30f);
    const int steps = std::min(64, std::max(1, static_cast<int>(std::ceil((s_hi - s_lo) / quarter))));
    // Bounds over the stretch on |w1| and |w2| across the ray (the ply centre's speed and
    // acceleration seen along the ray): the yarn's own direction counts only as far as it
    // crosses the ray, which is little at grazing views.
    const float kappa = length(c.curvature), s_max = std::max(std::fabs(s_lo), std::fabs(s_hi));
    const float speed_bound = across_length * (1 + m.offset * kappa) + m.offset * std::fabs(m.rate) +
                              kappa * s_max * (1 + m.offset * std::fabs(m.rate));
    // Higher derivatives: the bend, the ply's turn (offset rate^k) and its lean on the bend
    // (the tangent times s lean(phase), lean's k-th derivative at most offset kappa rate^k).
    const float rate = std::fabs(m.rate), lean = m.offset * kappa;
    const HelixBounds bounds{speed_bound, kappa + m.offset * rate * rate + lean * rate * (2 + s_max * rate),
                             m.offset * rate * rate * rate + lean * rate * rate * (3 + s_max * rate),
                             m.offset * sqr(sqr(rate)) + lean * rate * rate * rate * (4 + s_max * rate)};
    const float tolerance = options.tolerance * radius;
    // Crossings within a ply radius (N_i counts their plies), then entries in the order of a
    // lower bound on each (the approach less twice the straight cylinder's half chord and a
    // ply radius: a margin for the helix's bend) until no remaining one can come first.
    struct Reach {
        int ply;
        float s, approach, earliest;
    };
    Reach reached[64];
    int count = 0;
    uint32_t crossed = 0;
    LocalGrid grid;
    grid.build(m, std::min(plies, kMaxPlies), s_lo, s_hi, steps);
    for (int ply = 0; ply < plies && ply < kMaxPlies; ++ply) {
        const auto visit = [&](float sc, const Vec3& w, const Vec3& w1) {
            const float miss2 = m.miss2(w);
            if (miss2 > sqr(m.ply_radius + kGraze * tolerance) || count == 64) return;
            crossed |= 1u << ply;
            const float w1z = dot(w1, m.ray), pace = std::sqrt(std::max(dot(w1, w1) - w1z * w1z, 1e-12f));
            const float half_chord = std::sqrt(std::max(sqr(m.ply_radius) - miss2, 0.0f)) * length(w1) / pace;
            const float approach = dot(w, m.ray);
            int k = count++;
            for (; k > 0 && reached[k - 1].earliest > approach - 2 * half_chord - m.ply_radius; --k)
                reached[k] = reached[k - 1];
            reached[k] = {ply, sc, approach, approach - 2 * half_chord - m.ply_radius};
        };
        local_approaches(m, ply, plies, grid, bounds, tolerance, visit);
    }
    int best_ply = -1;
    float best_enter = 1e30f, best_s = 0;
    for (int k = 0; k < count && reached[k].earliest < best_enter; ++k) {
        float se = reached[k].s, enter;
        if (local_entry(m, reached[k].ply, plies, tolerance, s_hi - s_lo, reached[k].approach, se, enter) &&
            enter < best_enter) {
            best_enter = enter;
            best_ply = reached[k].ply;
            best_s = se;
        }
    }
    if (best_ply < 0) return pass();
    best_enter = std::max(best_enter, 0.0f);
    Candidate best{best_ply, local_cut(frames, at, m, d, tw, best_ply, best_s, hit.point)};
    best.enter = best_enter;
    PlyHit out = finish_hit(best, hit.point + hit.direction * best_enter, tw, hit);
    out.plies_crossed = __builtin_popcount(crossed);
    return out;
}

}  // namespace

PlyHit trace_plies_local(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& twist,
                         const YarnTubeHit& hit, const CentrelineProjection& around, const PlyTraceOptions& options) {
    return trace_local(frames, d, twist, hit, around, options, false);
}

PlyHit trace_plies(const CurveFrames& frames, const YarnDescription& d, const YarnTubeHit& hit,
                   const PlyTraceOptions& options) {
    return trace_plies(frames, d, yarn_twist(frames, d), hit, options);
}

PlyHit trace_plies(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                   const PlyTraceOptions& options) {
    switch (options.cross_section) {
        case PlyCrossSection::circular:
            return trace_circular(frames, d, tw, hit, project_to_centreline(frames, hit.point, hit.segment, hit.t));
        case PlyCrossSection::local:
            return trace_local(frames, d, tw, hit, project_to_centreline(frames, hit.point, hit.segment, hit.t),
                               options, true);
        default: {
            // One cache of segment expansions for the whole query, starting with the projection's.
            const CachedCurve cache(frames);
            return trace_elliptical(cache, d, tw, hit,
                                    project_to_centreline_unframed(cache, hit.point, hit.segment, hit.t), options);
        }
    }
}

}  // namespace purl
