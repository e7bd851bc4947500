// Implicit plies (Khattar et al. 2024, section 3.3): given a ray that entered the yarn tube,
// find the ply it meets, without any ply geometry in the scene.
//
// Elliptical cross-section (the paper's method): the plane that contains the ray and the
// direction across the yarn (T x w) cuts the tube in an ellipse. For every ply, Newton steps
// along the yarn, starting at the circular cross-section of the tube hit, move to where the
// ply's helix centre-line pierces that plane. The ray is then traced in the plane against
// each ply's cut (the ply taken as a cylinder along its helix tangent there); the nearest
// ply wins and N_i counts the plies the ray crosses. The winning hit is corrected once
// against the helix point closest to it, which matters on tight bends and at grazing angles.
//
// Circular cross-section (Zhu et al. 2023, the prototype; for comparison only): the plies are
// frozen in the tube's perpendicular cross-section at the hit and the ray is projected into it.
#pragma once
#include <cstdint>

#include "yarn/curve_frames.h"
#include "yarn/ply_helix.h"
#include "yarn/yarn_description.h"

namespace purl {

enum class PlyCrossSection {
    elliptical,             // plane through the ray, oriented by each ply's tangent (default)
    elliptical_yarn_plane,  // plane through the ray, oriented by the yarn's tangent (the paper, literally)
    circular,               // perpendicular cross-section at the hit (Zhu et al. 2023; comparison only)
};

struct PlyTraceOptions {
    PlyCrossSection cross_section = PlyCrossSection::elliptical;
    int max_iterations = 12;  // Newton steps per piercing before the fallback
    float tolerance = 1e-4f;  // yarn radii: a ply centre moving less than this has converged
    int refinements = 5;      // closest-point corrections of each candidate ply hit
    // The yarn stretch the ray crosses is scanned in sub-intervals of at most scan_turn radians
    // of ply turn and scan_length yarn radii (a closest approach hides in each at most once,
    // or shows in the slopes at its ends); near side views one interval suffices.
    float scan_turn = 1.5f;
    float scan_length = 2.0f;
};

// The renderer's yarn-tube hit: the ray and where it entered the tube.
struct YarnTubeHit {
    Vec3 origin, direction;  // the ray, direction unit length
    Vec3 point;              // entry point on the tube surface, m
    uint32_t segment = 0;    // centre-line parameter near the entry (Embree's u is close enough)
    float t = 0;
};

struct PlyHit {
    bool hit = false;       // false: pass-through, the ray crosses the yarn between plies
    int ply = -1;           // 0 .. N-1
    int plies_crossed = 0;  // N_i, plies the ray crosses in the cut (0 on pass-through)
    Vec3 point;             // on the ply surface, m
    Vec3 normal;            // unit, away from the ply centre-line, perpendicular to `tangent`
    Vec3 tangent;           // unit helix derivative (along increasing v)
    Vec3 outward;           // unit, from the yarn centre toward the ply centre, perpendicular to `tangent`
    float distance = 0;     // from the tube entry to `point` along the ray, m
    float exit_distance = 0;  // pass-through: from the tube entry to where the ray leaves the tube, m
    float u_ply = 0;        // rad in [0, 2 pi): angle of `normal` around the ply from `outward`
    float v_ply = 0;        // m along the ply from the curve's root
    float u_yarn = 0;       // rad in [0, 2 pi): azimuth of `point` around the yarn (RMF normal = 0)
    float v_yarn = 0;       // m along the yarn centre-line from the root
    float arrangement_azimuth = 0;  // rad in [0, 2 pi): u_yarn relative to ply 0 (G_p map coordinate)
    uint32_t segment = 0;   // centre-line parameter of the ply point's cross-section
    float t = 0;
    int iterations = 0;     // Newton steps, summed over the plies
    int max_ply_iterations = 0;  // most Newton steps any one ply needed
    bool converged = true;  // false when a ply fell back to the circular cross-section
};

// Never returns NaN: degenerate input (a ray along the yarn, a hit off the tube) gives a
// pass-through with a finite exit distance.
PlyHit trace_plies(const CurveFrames& frames, const YarnDescription& d, const YarnTubeHit& hit,
                   const PlyTraceOptions& options = {});

}  // namespace purl
