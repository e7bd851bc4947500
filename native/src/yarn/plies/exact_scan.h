// Crossings on the exact method's model (exact_model.h). Per ply, f(s) = p.p' across the ray
// is the function whose rising roots are its crossings: closest approaches of the centre-line
// to the ray, where D = |p|^2 across the ray is the squared miss distance. Every ply is checked
// at grid nodes kSubsteps per piece; an interval holds a crossing when f rises through zero,
// or two when the cubic through its ends' values and slopes turns back across zero (a ray
// grazing a ply between two close approaches).
#pragma once
#include "yarn/plies/exact_model.h"

namespace purl::plies {

constexpr int kSubsteps = 2;  // grid steps per piece at which every ply is checked
constexpr int kMaxWork = 64;  // model crossings solved per query at most

struct Sampled {
    float s, D, f, slope;  // arc length, D, f and df/ds
};

// D, f and df/ds in v (the piece's own parameter) from a ply centre's offset across the ray
// (px, py) and its first two derivatives in v. Per arc length, f is times dv/ds and df/ds
// times its square.
struct CrossingTerms {
    float D, f, slope;
};
inline CrossingTerms crossing_terms(float px, float dx, float ddx, float py, float dy, float ddy) {
    return {px * px + py * py, px * dx + py * dy, dx * dx + dy * dy + px * ddx + py * ddy};
}

// D, f and df/ds of one ply's model at arc length s (only the axes across the ray).
inline Sampled sample(const PlyPoly& q, float s) {
    const float v = (s - q.s0) * q.inv_h;
    float px, dx, ddx, py, dy, ddy;
    q.x.eval(v, px, dx, ddx);
    q.y.eval(v, py, dy, ddy);
    const CrossingTerms c = crossing_terms(px, dx, ddx, py, dy, ddy);
    return {s, c.D, c.f * q.inv_h, c.slope * q.inv_h * q.inv_h};
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
// derivative, its second derivative), so the grid's loops over plies vectorize: the arithmetic
// of YarnModel::ply and sample() (the same functions), lane by lane. Ply counts are padded to
// a multiple of 4 with copies of ply 0 (their results are never read).
struct PieceGrid {
    float x[15][kMaxPlies], y[15][kMaxPlies];
    float D[2][kMaxPlies], f[2][kMaxPlies], slope[2][kMaxPlies];  // at the previous and latest node

    // cp, sp: cos and sin of each ply's offset, padded like the plies.
    void set(const Piece& q, const float* cp, const float* sp, int plies);
    // Every ply at v into slot `to` (0 or 1).
    void node(int plies, float v, float ih, int to);
};

// A bracket of one crossing of one ply.
struct Work {
    int ply;
    Sampled lo, hi;
};

// The current piece's plies as PlyPolys, each built when first asked for (the grid has its own
// copy of the coefficients; only plies with work need these).
struct PiecePlies {
    const YarnModel* model = nullptr;
    int piece = 0;
    uint32_t built = 0;
    Slots<PlyPoly, kMaxPlies> items;  // left uninitialized until built

    void reset(const YarnModel& m, int j) {
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

// The brackets found in one piece: intervals between grid nodes that may hold a crossing.
struct Brackets {
    PiecePlies* polys = nullptr;  // the current piece's plies
    float reach2 = 0;             // (ply radius + model margin)^2: a closer approach may be a crossing
    float speed = 0, accel = 0;   // bounds on |p'| and |p''| over the current piece
    Work work[kMaxWork];
    int count = 0;

    // Bounds on a ply centre's speed and acceleration over piece q, for out_of_reach.
    void bound(const YarnModel& m, const Piece& q);
    // Looks into one interval of one ply (split at most twice where f may turn back).
    void interval(int ply, const Sampled& a, const Sampled& b, int depth);
};

// Safeguarded Newton steps on the model inside a bracket, from the secant point. False when
// max_steps are not enough.
bool solve(const PlyPoly& q, const Work& w, float tolerance, int max_steps, float& s);

}  // namespace purl::plies
