// The fiber-based reference's geometry: procedural fibers after Zhao, Luan and Bala 2016
// ("Fitting procedural yarn models"), each its own round B-spline curve of radius
// fiber_radius x ply radius, twisted around the same ply helices as the implicit model.
//
// Per ply, fiber k has a rest position (r_k, theta_k) in the ply cross-section (ply radii),
// drawn by rejection from Zhao's density p(R) = (1 - 2 eps) ((e - e^R) / (e - 1))^beta + eps
// and scaled by (1 - fiber_radius) so that the whole fiber stays inside its ply (and the ply
// inside the yarn). Along the yarn (v = ply length, YarnTwist rates):
//   theta(v) = theta_k + fiber_rate v                                  fiber twist
//   r(v)     = r_k (rho_min + (rho_max - rho_min) (cos(s_i |fiber_rate| v + phi_k) + 1) / 2)   migration
//   P(v)     = ply centre + r(v) ply_radius (cos theta e_1 + sin theta e_2)
// with e_1 the ply's outward direction (yarn centre -> ply centre, made normal to the ply
// tangent) and e_2 = ply tangent x e_1: the frame the implicit fiber maps use. On closed loops
// the migration rate is rounded to whole cycles per loop so fibers meet themselves at the seam.
// Flyaways are not generated. Random numbers depend on (description seed, curve key, ply).
#pragma once
#include <cstdint>
#include <vector>

#include "reference/explicit_sampling.h"

namespace purl {

struct FiberRest {
    float radius = 0;           // r_k, ply radii (already scaled by 1 - fiber_radius)
    float angle = 0;            // theta_k, rad from e_1
    float migration_phase = 0;  // phi_k, rad
};

// The fibers of one ply: the same for a given (seed, curve_key, ply).
std::vector<FiberRest> ply_fiber_rest_positions(const YarnDescription& d, uint32_t curve_key, int ply);

// Appends every fiber of every ply of one yarn curve to `out` (ply-major), curve id `id`.
// `curve_key` decorrelates the fiber layouts of different yarns.
void append_fiber_curves(const CurveFrames& frames, const YarnDescription& d, const CurveSampling& plan,
                         uint32_t curve_key, int32_t id, YarnCurves& out);

}  // namespace purl
