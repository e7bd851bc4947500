// The ply-level four-lobe model of the ply-based reference (Montazeri et al. 2020, "A
// practical ply-based appearance model of woven fabrics"): f_x^S, f_y^S, f_x^B, f_y^B on one
// explicit ply, with fiber detail (normal, tangent, G_f) from the same fiber maps as the BYSDF.
//
// It is the BYSDF (bysdf.h, docs/bysdf.md) evaluated at one ply: N_i = 1 (a transmitted ray
// crosses only the ply it hit; further plies are met by the path tracer) and G_p = 1 (inter-ply
// shadowing comes from real occlusion between the ply curves). The chord is the path through
// the hit ply's own tube, still in yarn radii, so sigma_t keeps its meaning. Same parameters,
// same lobes, same sampling: only the geometry that feeds it changes.
#pragma once
#include "bsdf/bysdf.h"

namespace purl {

// G_f in [0, 1] from the fiber maps; ply_index selects the ply colour.
inline Bysdf make_ply_bsdf(const BysdfParams& params, float fiber_shadow, int ply_index, Vec3 yarn_color = Vec3(1.0f)) {
    BysdfShadingPoint point;
    point.ply_shadow = 1.0f;  // occlusion between plies is traced, not mapped
    point.fiber_shadow = fiber_shadow;
    point.plies_crossed = 1;
    point.ply_index = ply_index;
    point.yarn_color = yarn_color;
    return Bysdf(params, point);
}

}  // namespace purl
