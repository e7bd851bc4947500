// Implicit plies (Khattar et al. 2024, section 3.3): given a ray that entered the yarn tube,
// find the ply it meets, without any ply geometry in the scene. Plies are the helices of
// ply_helix.h; docs/implicit-geometry.md has the algorithm and the measured accuracy. The
// search's parts are in yarn/plies/, one file per method:
//
// elliptical (default, plies/exact*): for every ply, where its centre-line crosses a plane
// through the ray. The plane holds the ray and the direction perpendicular to both the ray and
// the ply's own tangent, so the ply's cut in it is an ellipse centred on the crossing, and the
// crossings are the centre-line's closest approaches to the ray. One model of the yarn per
// query (its centre-line and frame over the stretch the ray crosses, interpolated between a
// few exact frames and expressed in the ray's coordinates) gives every ply's crossings, miss
// distances and entries with a sine-free per-ply loop; only the winning ply's entry (and any
// crossing the model cannot decide) is refined on the exact curve, so the result is that of
// exact Newton steps. A crossing within the ply radius is a ply the ray crosses (N_i).
//
// local (plies/local*): the same crossings on the yarn straightened to second order at the hit
// (centre-line c + T s + kappa s^2 / 2, frame turned to first order), so every ply is an
// analytic helix and the query needs no curve evaluation: exact on straight yarns, approximate
// on bends. Multi-scale's virtual rays use it around the camera ray's cross-section.
//
// circular (Zhu et al. 2023, the prototype; plies/circular): plies frozen in the perpendicular
// cross-section at the hit. For comparison.
#pragma once
#include <cstdint>

#include "base/registry.h"  // PlyCrossSection
#include "yarn/curve_frames.h"
#include "yarn/ply_helix.h"
#include "yarn/yarn_description.h"
#include "yarn/yarn_tube.h"

namespace purl {

struct PlyTraceOptions {
    PlyCrossSection cross_section = PlyCrossSection::elliptical;
    int max_iterations = 12;  // Newton steps per crossing (on the exact method's model) before the fallback
    float tolerance = 1e-4f;  // yarn radii: a ply centre moving less than this has converged
    int refinements = 5;      // closest-point corrections of each candidate ply hit
    // The exact method's model of the yarn over the ray's stretch is built from exact frames at
    // most model_turn radians of ply turn and model_length yarn radii apart.
    float model_turn = 1.5f;
    float model_length = 2.0f;
    // Yarn radii the model may be off by: a crossing whose model miss distance is within this
    // of the ply radius is settled on the exact curve, and exact entries are refined until the
    // next model entry, less this margin (over the cosine of incidence), is past the best one.
    // A large value resolves every crossing exactly (slow; for tests). On knitted cloth the
    // model is off by up to ~0.05 R (curvature changes within a piece): with this default,
    // 11,999 of 12,000 cloth rays get the answer a margin of 1 R gives (0.005 R: 11,954).
    float model_margin = 0.05f;
};

// The renderer's yarn-tube hit: the ray and where it entered the tube.
struct YarnTubeHit {
    Vec3 origin, direction;  // the ray, direction unit length
    Vec3 point;              // entry point on the tube surface, m
    uint32_t segment = 0;    // centre-line parameter near the entry (Embree's u is close enough)
    float t = 0;
};

// One ply search: a ray that entered a yarn's tube, and the yarn.
struct PlyQuery {
    const CurveFrames& frames;  // the yarn's centre-line and its frames
    const YarnDescription& yarn;
    const YarnTwist& twist;     // yarn_twist(frames, yarn), kept per curve by the renderer
    const YarnTubeHit& ray;     // the ray and where it entered the tube
    // The local method models the yarn around this cross-section when given (a centre-line
    // projection near the entry already at hand, e.g. a neighbouring parallel ray's: no curve
    // evaluation at all); otherwise around the entry's own projection. The others ignore it.
    const CentrelineProjection* around = nullptr;
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
};

// What one search spent, for tests and benchmarks (the answer does not depend on it).
struct PlySearchStats {
    int evaluations = 0;          // exact curve evaluations (model frames, refinements)
    int max_ply_evaluations = 0;  // most exact curve evaluations one ply's entry refinement needed
    bool converged = true;        // false when a ply fell back to the circular cross-section
};

// Never returns NaN: degenerate input (a ray along the yarn, a hit off the tube) gives a
// pass-through with a finite exit distance.
PlyHit trace_plies(const PlyQuery& query, const PlyTraceOptions& options = {}, PlySearchStats* stats = nullptr);

}  // namespace purl
