// Implicit plies against explicit ones (explicit_plies.h): the sweep behind the accuracy test,
// the map tool (tools/yarn_maps) and the numbers in docs/implicit-geometry.md.
//
// Test yarns have radius 1 (everything is in yarn radii): straight (along +z) or a closed
// circular loop of a given curvature radius. Rays come from a random side of the yarn at a
// fixed angle psi from the yarn's normal plane, with a uniform offset across the tube; the
// tube entry comes from the explicit tube, as Embree would give it.
#pragma once
#include <cstdint>
#include <vector>

#include "reference/explicit_plies.h"
#include "yarn/implicit_plies.h"
#include "yarn/yarn_description.h"

namespace purl {

// Plies of radius r touching each other and filling 97% of the tube: d (1 + sin(pi/N)) = 0.97.
YarnDescription touching_plies(int plies, float ply_twist = 2.0f / 3.0f);

// Control points (radius 1) of a straight yarn (curvature_radius <= 0) or a closed loop.
std::vector<Vec4> validation_curve(float curvature_radius);

struct ValidationCase {
    YarnDescription description = touching_plies(3);
    float view_angle = 0;        // psi, degrees from the yarn's normal plane (0 = side view)
    float curvature_radius = 0;  // yarn radii; <= 0 for a straight yarn
    int rays = 1000;
    uint64_t seed = 1;
    int count_crossings_every = 4;  // explicit N_i (one trace per ply) on every k-th ray; 0: never
};

struct MethodStats {
    int rays = 0;               // rays compared (the reference resolved them)
    int agree = 0;              // hit/miss agrees with the explicit plies
    int both_hit = 0;
    int same_ply = 0;           // both hit, and the same ply
    int false_hits = 0;         // implicit hit, explicit miss
    int false_misses = 0;       // implicit miss, explicit hit
    int unconverged = 0;        // a ply fell back to the circular cross-section
    int non_finite = 0;         // any NaN or infinity in the output (must stay 0)
    int crossed_checked = 0;    // both hit and the explicit N_i was counted (every fourth ray)
    int crossed_agree = 0;      // ... and N_i equals it
    std::vector<float> normal_error;   // degrees, rays where both hit the same ply
    std::vector<float> tangent_error;  // degrees, rays where both hit the same ply
    std::vector<float> distance_error;  // yarn radii along the ray, same rays
    std::vector<int> iterations;       // most exact curve evaluations one ply's refinement needed, per ray

    double agreement() const { return rays ? double(agree) / rays : 1.0; }
    double mean(const std::vector<float>& v) const;
    double percentile(std::vector<float> v, double p) const;
};

struct ValidationResult {
    int reference_unresolved = 0;  // rays dropped because the explicit trace ran out of steps
    MethodStats elliptical, circular;
};

// `elliptical_options` configures the method reported as `elliptical` (any method);
// `circular` always uses the circular cross-section.
ValidationResult validate_plies(const ValidationCase& c, const PlyTraceOptions& elliptical_options = {});

// The explicit plies' answer at a tube hit, for any yarn (cloth included), as a PlyHit: the
// ray from the tube entry to where it leaves the tube (a later passage through the same yarn
// is another query), the first ply it enters, N_i by one trace per ply. `converged` is false
// when there is nothing to compare with: the explicit trace ran out of steps, or a ply it
// meets lies farther along the yarn than this passage reaches (another passage of the same
// yarn, overlapping this one's tube, as a knit's touching loops do). `evaluations` holds the
// explicit trace's step count.
PlyHit explicit_ply_answer(const CurveFrames& frames, const ExplicitPlies& plies, int ply_count,
                           const YarnTubeHit& hit, PlySearchStats* stats = nullptr);
// Adds one ray to `m`: how an implicit answer (and what its search spent) compares with the
// explicit one (N_i only when count_crossings, since the explicit N_i is costly).
void compare_with_explicit(MethodStats& m, const PlyHit& implicit, const PlySearchStats& spent,
                           const PlyHit& reference, bool count_crossings);

// An orthographic picture of one case for the Fig. 3-style maps: per pixel, whether each
// method (and the reference) hit a ply and the ply tangents. Straight yarns are seen at
// view_angle; loops are seen from above their plane (their yarn normal view, plus view_angle tilt).
struct ValidationImage {
    int width = 0, height = 0;
    // Per pixel, row-major; tangents are zero where nothing was hit.
    std::vector<uint8_t> tube, explicit_hit, elliptical_hit, circular_hit;
    std::vector<Vec3> explicit_tangent, elliptical_tangent, circular_tangent;
    std::vector<Vec3> explicit_normal, elliptical_normal, circular_normal;
};
ValidationImage render_validation_image(const ValidationCase& c, int width, int height);

}  // namespace purl
