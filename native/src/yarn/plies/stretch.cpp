#include "yarn/plies/stretch.h"

#include <algorithm>
#include <cmath>

namespace purl::plies {

Stretch ray_stretch(const CachedCurve& frames, const YarnDescription& d, const YarnTubeHit& hit,
                    const CentrelineProjection& at, float tan_psi) {
    const CurvePoint& c = at.point;
    const float radius = c.radius;
    const StraightStretch straight = straight_stretch(c, radius, d.ply_radius * radius, hit, tan_psi, 0.0f);
    Stretch st;
    st.exit_distance = -1;
    const double g0 = at.segment + double(at.t), inv_speed = 1.0 / std::max(c.speed, 1e-30f);
    st.g_lo = g0 + straight.lo * inv_speed;
    st.g_hi = g0 + straight.hi * inv_speed;
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
        const double pad = straight.margin * inv_speed;
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

}  // namespace purl::plies
