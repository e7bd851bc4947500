// What the renderer hands to the BYSDF at a yarn hit (Khattar et al. 2024, sections 3.3-3.4):
// the implicit ply hit turned into a fiber frame, n_f = n'(R(n_p)) and t_f = t'(R(t_p)):
// the fiber map rotates the ply normal about the ply tangent by the visible fiber's normal
// angle, and the fiber's helix around the ply tilts the tangent toward that fiber's own
// azimuthal direction by atan(fiber_rate * distance); the normal is then made perpendicular
// to the tangent. Plus N_i, G_p, G_f and the ply index.
#pragma once
#include <cstdint>

#include "yarn/curve_frames.h"
#include "yarn/fiber_maps.h"
#include "yarn/implicit_plies.h"
#include "yarn/yarn_description.h"

namespace purl {

struct YarnShadingPoint {
    bool hit = false;           // false: pass-through, continue the ray `exit_distance` further
    Vec3 position;              // on the ply surface, m
    Vec3 fiber_normal;          // unit: the shading normal
    Vec3 fiber_tangent;         // unit, perpendicular to fiber_normal: the shading tangent
    Vec3 ply_normal, ply_tangent;  // unit, before the fiber maps
    int ply_index = -1;
    int plies_crossed = 0;      // N_i (the BYSDF wants at least 1 on a hit)
    float ply_shadowing = 1;    // G_p in [0, 1], no floor applied
    float fiber_shadowing = 1;  // G_f in [0, 1], no floor applied
    float u_ply = 0, v_ply = 0;    // rad, m
    float u_yarn = 0, v_yarn = 0;  // rad, m
    float distance = 0;         // from the tube entry to `position` along the ray, m
    float exit_distance = 0;    // pass-through: from the tube entry to where the ray leaves the tube, m
    uint32_t segment = 0;       // centre-line parameter of the ply point's cross-section (for
    float t = 0;                //   tube_chord_length from `position`)
};

// Fiber frame and maps for an implicit ply hit. `curve_key` (e.g. the curve index) decorrelates
// the migration pattern between yarns.
YarnShadingPoint shade_ply_hit(const PlyHit& hit, const CurveFrames& frames, const YarnDescription& d,
                               const FiberMaps& maps, uint32_t curve_key);
// The same with the curve's twist rates at hand (yarn_twist(frames, d)).
YarnShadingPoint shade_ply_hit(const PlyHit& hit, const CurveFrames& frames, const YarnDescription& d,
                               const YarnTwist& twist, const FiberMaps& maps, uint32_t curve_key);

// trace_plies followed by shade_ply_hit: the whole implicit query for one yarn-tube hit.
YarnShadingPoint trace_yarn_hit(const CurveFrames& frames, const YarnDescription& d, const FiberMaps& maps,
                                const YarnTubeHit& hit, uint32_t curve_key, const PlyTraceOptions& options = {});
// The same with the curve's twist rates at hand, as the renderer keeps them per curve.
YarnShadingPoint trace_yarn_hit(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& twist,
                                const FiberMaps& maps, const YarnTubeHit& hit, uint32_t curve_key,
                                const PlyTraceOptions& options = {});

}  // namespace purl
