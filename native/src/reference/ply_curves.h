// The ply-based reference's geometry (Montazeri et al. 2020): every ply of a yarn as its own
// round B-spline curve. The curve passes through ply_centre() (yarn/ply_helix.h, the same
// helix the implicit model traces) at knots evenly spaced along the yarn, with radius
// ply_radius x yarn radius; between knots it stays within ExplicitOptions::ply_tolerance.
#pragma once
#include <cstdint>
#include <vector>

#include "reference/explicit_sampling.h"
#include "scene/scene.h"

namespace purl {

// The yarn parameter of knot j of a ply curve: arc length j * plan.step.
inline float knot_arc_length(const CurveSampling& plan, uint32_t j) { return plan.step * float(j); }

// Appends the d.plies() ply curves of one yarn curve to `out` (ply i after ply i-1), each with
// curve id `id`, and their origins to `origins` (yarn_curve = `yarn_curve`).
void append_ply_curves(const CurveFrames& frames, const YarnDescription& d, const CurveSampling& plan,
                       uint32_t yarn_curve, int32_t id, YarnCurves& out, std::vector<PlyCurveOrigin>& origins);

}  // namespace purl
