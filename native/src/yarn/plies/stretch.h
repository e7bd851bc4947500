// The stretch of yarn a ray crosses: where along the yarn a ply can meet it. Every method
// searches only there.
#pragma once
#include <algorithm>
#include <cmath>

#include "yarn/plies/result.h"

namespace purl::plies {

// Arc lengths from the cross-section c (m) over which the ray runs inside the straight tube
// there, from the tube entry at arc length `entry_s` from c, widened by how far along the yarn
// a ply's cut can reach: a ply radius over the view's tangent tan_psi, 0.05 R for the bend,
// and a tenth of the chord's run along the yarn.
struct StraightStretch {
    float lo, hi;
    float margin;  // the widening at either end, m
};
inline StraightStretch straight_stretch(const CurvePoint& c, float radius, float ply_radius, const YarnTubeHit& hit,
                                        float tan_psi, float entry_s) {
    const float chord = ray_cylinder(hit.point, hit.direction, c.position, c.tangent, radius).chord();
    const float along = dot(hit.direction, c.tangent);
    StraightStretch st;
    st.margin = ply_radius * (1 + tan_psi) + 0.05f * radius + 0.1f * chord * std::fabs(along);
    st.lo = entry_s + std::min(0.0f, chord * along) - st.margin;
    st.hi = entry_s + std::max(0.0f, chord * along) + st.margin;
    return st;
}

// The exact method's stretch: the straight tube's (on bends, from the entry to the real exit),
// clipped to open yarns' ends, in curve parameters and in arc lengths from the projection `at`
// of the tube entry.
struct Stretch {
    double g_lo, g_hi;
    float s_lo, s_hi;
    float exit_distance;  // on bends, where the ray leaves the tube (m from the entry); else -1
};
Stretch ray_stretch(const CachedCurve& frames, const YarnDescription& d, const YarnTubeHit& hit,
                    const CentrelineProjection& at, float tan_psi);

}  // namespace purl::plies
