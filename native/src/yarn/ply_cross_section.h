// Procedural cross-sections in 2D, the raw material of the 1D maps (fiber_maps.h):
//  - a ply's fibers (Zhao, Luan and Bala 2016): centres drawn by rejection from the radial
//    density p(R) = (1 - 2 eps) ((e - exp(R)) / (e - 1))^beta + eps (R in ply radii), each
//    fiber migrating between rho_min and rho_max times its rest distance;
//  - a yarn's plies: N circles of radius ply_radius at ply_distance (yarn radii).
#pragma once
#include <vector>

#include "math/vec.h"
#include "yarn/yarn_description.h"

namespace purl {

// Zhao's relative density of fiber centres at distance r (ply radii, 0..1) from the ply centre.
float fiber_density(float r, float eps, float beta);

struct Circles2D {
    std::vector<Vec2> centres;
    float radius = 0;  // all circles share it

    // First circle hit by the 2D ray o + t d (d unit), t > t_min; -1 when none. `skip` is ignored.
    int first_hit(Vec2 o, Vec2 d, float t_min, float& t, int skip = -1) const;
};

// The fibers of one ply (ply radii) at a point of their migration cycle: every call shares the
// fibers' rest positions (from the description's seed); migration_phase (rad) moves them all
// along their cycles, each from its own random start.
Circles2D ply_fibers(const YarnDescription& d, float migration_phase);

// The plies of the yarn (yarn radii), ply i at angle 2 pi i / N.
Circles2D yarn_plies(const YarnDescription& d);

// Share of a cosine-weighted half-circle of directions around `normal` at `point` that hit a
// circle other than `self`: the 2D ambient occlusion used by G_f and G_p.
float occlusion_2d(const Circles2D& circles, Vec2 point, Vec2 normal, int self, int directions = 64);

}  // namespace purl
