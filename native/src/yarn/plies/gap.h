// How far a ray point is outside a ply, measured to the helix point closest to it: the exact
// and local methods' bracketed entry search (bracketed_entry.h) runs on this gap.
//
// A Helix walks one ply's centre-line (the exact curve, or the local method's analytic helix):
//   Point                       a helix point, as the walk carries it
//   HelixPoint view(Point)      its position, derivatives in yarn arc length and ply radius
//   Point moved(Point, ds)      the helix point ds m of yarn further on
//   Vec3 ray_at(lambda)         the ray point lambda m from the tube entry
//   float step_limit()          the longest step along the yarn the walk may take, m
#pragma once
#include <cmath>

#include "yarn/plies/result.h"

namespace purl::plies {

struct HelixPoint {
    Vec3 position, d1, d2;  // m, and d/ds, d2/ds2 in yarn arc length
    float radius;           // ply radius, m
};

// Distance from the ray point at `lambda` to the ply surface (negative inside), with `p` moved
// to the helix point closest to it (a few Newton steps, each evaluated). Measured to that
// helix point itself, not to the line along its tangent: if the steps stop short of the
// closest point, the distance is still an upper bound, so a point outside the ply is never
// taken for one inside.
template <class Helix>
float helix_gap(Helix& helix, float lambda, typename Helix::Point& p) {
    const Vec3 x = helix.ray_at(lambda);
    for (int step = 0; step < 6; ++step) {
        const HelixPoint h = helix.view(p);
        const float ds = clamp(closest_point_step(h.position, h.d1, h.d2, x), -helix.step_limit(), helix.step_limit());
        p = helix.moved(p, ds);
        if (std::fabs(ds) < 1e-4f * helix.view(p).radius) break;
    }
    const HelixPoint h = helix.view(p);
    return length(x - h.position) - h.radius;
}

}  // namespace purl::plies
