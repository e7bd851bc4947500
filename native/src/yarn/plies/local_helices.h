// The local method's yarn: straightened, to second order, at one cross-section (arc length s
// from it). The centre-line is c + T s + kappa s^2 / 2 and the rotation-minimizing frame turns
// as N(s) = N - (N.kappa) s T (likewise B), so ply i is an analytic helix in s with phase
// phi_i + rate s: crossings and entries need only sines, no curve evaluation. Exact on
// straight yarns; on bends the error grows as |kappa|^2 s^3, i.e. with the stretch an oblique
// ray crosses (docs/implicit-geometry.md has the measurements).
#pragma once
#include <algorithm>
#include <cmath>

#include "math/fast_trig.h"
#include "yarn/plies/result.h"

namespace purl::plies {

// The straightened yarn's axes: in world coordinates (V = Vec3, c relative to the tube entry),
// or seen along the ray in coordinates across it (V = Vec2).
template <class V>
struct HelixAxes {
    V c, tangent, kappa, normal, binormal;
};

// A ply centre relative to the tube entry (w) and its derivatives in s (w1, w2), given the
// cosine and sine of the ply's phase at s; offset: the ply distance (m), rate: its turn (rad/m),
// nk, bk: N.kappa and B.kappa. One formula for the world and the across-the-ray view; the
// latter has the ply distance folded into its normal and binormal (scaled_frame: two products
// fewer per node of the vectorised scan).
template <bool scaled_frame, class V>
inline void straightened_helix(const HelixAxes<V>& a, float nk, float bk, float offset, float rate, float s, float cp,
                               float sp, V& w, V& w1, V* w2) {
    const V out = a.normal * cp + a.binormal * sp, around = a.binormal * cp - a.normal * sp;
    const float lean = 1 - offset * (nk * cp + bk * sp), turn = offset * rate * (bk * cp - nk * sp);
    if constexpr (scaled_frame) {
        w = a.c + a.kappa * (0.5f * s * s) + out + a.tangent * (s * lean);
        w1 = a.kappa * s + around * rate + a.tangent * (lean - s * turn);
        if (w2) *w2 = a.kappa - out * (rate * rate) - a.tangent * (2 * turn);
    } else {
        w = a.c + a.kappa * (0.5f * s * s) + out * offset + a.tangent * (s * lean);
        w1 = a.kappa * s + around * (offset * rate) + a.tangent * (lean - s * turn);
        if (w2) *w2 = a.kappa - out * (offset * rate * rate) - a.tangent * (2 * turn);
    }
}

struct LocalHelices {
    HelixAxes<Vec3> world;     // at the modelled cross-section; c relative to the tube entry
    HelixAxes<Vec2> across;    // the same seen along the ray, normal and binormal times the ply
                               // distance: all a scan node needs, at two thirds of the work
    Vec3 ray;                  // unit ray direction
    float nk = 0, bk = 0;      // N.kappa, B.kappa
    float offset = 0, ply_radius = 0, rate = 0, phase = 0;  // ply distance (m), radius (m), rad/m, ply 0 at s = 0
    float offsets[kMaxPlies];  // 2 pi i / N of ply i, set by set_offsets

    // u: unit, across the ray (and the yarn); after `world`, `ray` and `offset` are set.
    void set_across(Vec3 u) {
        const Vec3 v = cross(ray, u);
        const auto view = [&](Vec3 x) { return Vec2(dot(x, u), dot(x, v)); };
        across = {view(world.c), view(world.tangent), view(world.kappa), view(world.normal * offset),
                  view(world.binormal * offset)};
    }
    void set_offsets(int plies) {
        for (int i = 0; i < kMaxPlies; ++i) offsets[i] = i < plies ? 2 * kPi * i / plies : 0.0f;
    }
    void phase_at(int ply, float s, float& cp, float& sp) const { fast_sincos(phase + rate * s + offsets[ply], cp, sp); }
    void at(float s, float cp, float sp, Vec3& w, Vec3& w1, Vec3* w2) const {
        straightened_helix<false>(world, nk, bk, offset, rate, s, cp, sp, w, w1, w2);
    }
    // Ply `ply` at s.
    void at(int ply, float s, Vec3& w, Vec3& w1, Vec3* w2) const {
        float cp, sp;
        phase_at(ply, s, cp, sp);
        at(s, cp, sp, w, w1, w2);
    }
    // Across-the-ray parts: the crossing condition f = w_perp . w1_perp and its slope.
    float crossing(const Vec3& w, const Vec3& w1, const Vec3* w2 = nullptr, float* slope = nullptr) const {
        const float wz = dot(w, ray), w1z = dot(w1, ray);
        if (slope) *slope = dot(w1, w1) - w1z * w1z + dot(w, *w2) - wz * dot(*w2, ray);
        return dot(w, w1) - wz * w1z;
    }
    float miss2(const Vec3& w) const {
        const float wz = dot(w, ray);
        return dot(w, w) - wz * wz;
    }
};

struct LocalNode {
    float s, f, miss, pace;  // arc length, crossing function, distance from the ray (m), |w1 across the ray|
};

// A scan node from the cosine and sine of the ply's phase at s.
inline LocalNode node_at(const LocalHelices& m, float s, float cp, float sp) {
    Vec2 w, w1;
    straightened_helix<true>(m.across, m.nk, m.bk, m.offset, m.rate, s, cp, sp, w, w1, static_cast<Vec2*>(nullptr));
    return {s, dot(w, w1), length(w), length(w1)};
}
// The same for ply `ply` (scan subdivisions and huge phases only: out of line).
LocalNode local_node(const LocalHelices& m, int ply, float s);

// Bounds over a query's stretch on the derivatives of a ply centre seen across the ray
// (m per m of s to the k-th power): |w1|, |w2|, |w3|, |w4|.
struct HelixBounds {
    float speed, bend, jerk, snap;
};

// Every lane (ply) at s, phases reduced by quarter_turns: one loop the compiler vectorises.
inline void grid_nodes(const LocalHelices& m, int lanes, float s, float* __restrict f, float* __restrict miss,
                       float* __restrict pace) {
    for (int i = 0; i < lanes; ++i) {
        const float a = m.phase + m.rate * s + m.offsets[i];
        float cp, sp;
        quadrant_sincos(a, quarter_turns(a), cp, sp);
        const LocalNode n = node_at(m, s, cp, sp);
        f[i] = n.f, miss[i] = n.miss, pace[i] = n.pace;
    }
}

// The scan's grid nodes for every ply (node k of ply i at [k * kMaxPlies + i]), built in one
// pass over the plies per node that the compiler vectorises: node_at lane by lane. Phases too
// large for quarter_turns take local_node.
struct LocalGrid {
    static constexpr int kMaxNodes = 65;
    int steps = 0;  // intervals between the nodes
    Slots<float, kMaxNodes> s;
    Slots<float, kMaxNodes * kMaxPlies> f, miss, pace;

    // In the header so that trace_local can inline it: out of line, the local query took 2 %
    // more instructions (forcing it inline put more of the query out of the instruction cache).
    void build(const LocalHelices& m, int plies, float s_lo, float s_hi, int intervals) {
        steps = intervals;
        const int lanes = padded_plies(plies);
        const float h = (s_hi - s_lo) / steps;
        const bool fits =
            std::fabs(m.phase) + std::fabs(m.rate) * std::max(std::fabs(s_lo), std::fabs(s_hi)) + 2 * kPi < 6.5e6f;
        for (int k = 0; k <= steps; ++k) {
            const float at = k == steps ? s_hi : s_lo + h * k;
            s[k] = at;
            if (fits) {
                grid_nodes(m, lanes, at, &f[k * kMaxPlies], &miss[k * kMaxPlies], &pace[k * kMaxPlies]);
                continue;
            }
            for (int i = 0; i < plies; ++i) {
                const LocalNode n = local_node(m, i, at);
                f[k * kMaxPlies + i] = n.f, miss[k * kMaxPlies + i] = n.miss, pace[k * kMaxPlies + i] = n.pace;
            }
        }
    }
    LocalNode node(int k, int ply) const {
        return {s[k], f[k * kMaxPlies + ply], miss[k * kMaxPlies + ply], pace[k * kMaxPlies + ply]};
    }
};

}  // namespace purl::plies
