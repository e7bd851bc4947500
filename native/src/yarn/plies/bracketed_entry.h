// Where the ray enters a ply when walking cylinders along the helix does not settle (a ray
// almost along the ply): regula falsi on the gap to the helix (gap.h) between the tube entry,
// which must be outside the ply (else the ray starts in it), and the closest approach, which
// must be inside. Both the exact and the local method end their entry search here.
#pragma once
#include "yarn/plies/gap.h"

namespace purl::plies {

// `start`: the helix point near the crossing; `approach`: the closest approach's ray distance;
// `graze`: how far outside the ply the closest approach may pass and still touch it (m).
// False when the ray misses the ply; else `at` and `enter` are the entry's helix point and
// ray distance, to `tolerance`.
template <class Helix>
bool bracketed_entry(Helix& helix, const typename Helix::Point& start, float approach, float graze, float tolerance,
                     typename Helix::Point& at, float& enter) {
    using Point = typename Helix::Point;
    float lo = 0, hi = std::max(approach, 0.0f);
    Point lo_at = start, hi_at = start;
    float gap_lo = helix_gap(helix, lo, lo_at);
    if (gap_lo <= 0) {
        at = lo_at;
        enter = 0;
        return true;
    }
    float gap_hi = helix_gap(helix, hi, hi_at);
    if (gap_hi > graze) return false;
    if (gap_hi > 0) {  // a graze: touching at the approach
        at = hi_at;
        enter = hi;
        return true;
    }
    for (int step = 0; step < 30 && hi - lo > tolerance; ++step) {
        float mid = (lo * gap_hi - hi * gap_lo) / (gap_hi - gap_lo);
        if (!(mid > lo + 0.05f * (hi - lo) && mid < hi - 0.05f * (hi - lo))) mid = 0.5f * (lo + hi);
        Point mid_at = gap_hi > -gap_lo ? lo_at : hi_at;
        const float gap = helix_gap(helix, mid, mid_at);
        if (gap > 0) lo = mid, gap_lo = gap, lo_at = mid_at;
        else hi = mid, gap_hi = gap, hi_at = mid_at;
    }
    at = hi_at;
    enter = hi;
    return true;
}

}  // namespace purl::plies
