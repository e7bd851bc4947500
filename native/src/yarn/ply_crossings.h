// The plies a ray leaving a ply hit crosses before it leaves the yarn tube, and how far it
// runs inside each: what light scattered at x meets on its way out through the rest of the
// yarn (the explicit ply reference traces these plies; the BYSDF's "traced" ply crossing
// takes them from here, docs/bysdf.md).
//
// The yarn is taken as straight over the ray's chord (at most one diameter), in yarn radii,
// with the plies as the helices of ply_helix.h turning at twist.ply_rate. A ply's cut by a
// plane perpendicular to the yarn is an ellipse: radius ply_radius across, ply_radius x
// ply_stretch around the yarn (the helix leans by atan(ply_distance R ply_rate)). The chord is
// marched in steps of a quarter ply radius, boundaries interpolated inside a step; against
// the true helix tubes of a straight yarn the lengths inside plies are within a few per cent
// (tests/native/yarn/test_ply_crossings.cpp).
#pragma once

#include "math/vec.h"
#include "yarn/curve_frames.h"
#include "yarn/ply_helix.h"
#include "yarn/yarn_description.h"

namespace purl {

constexpr int kMaxCrossedPlies = 12;  // YarnDescription's ply_count limit

// Spread crossing (ply_crossing 2): light another ply scatters reaches the hit from around the
// ray, not only along it; four directions tilted by 20 degrees stand for that cone (measured on
// the 6-ply Fig. 7 yarn: 10-30 degrees give FLIP within 0.003 of each other, docs/bysdf.md).
constexpr int kSpreadDirections = 4;
constexpr float kSpreadAngle = 20.0f * kPi / 180.0f;

// A ply hit in the straight-yarn model, every length in yarn radii.
struct PlySection {
    Vec3 tangent;        // unit yarn tangent
    // The cross-section the section was taken at need not hold the hit (the implicit plies
    // report the one where they found the ply centre): the hit may lie along the tangent.
    Vec3 hit_outward;    // unit, perpendicular to tangent: from the yarn centre toward the hit ply's centre there
    Vec3 offset;         // the hit point minus that cross-section's centre-line point
    float ply_turn = 0;  // rad of ply phase per yarn radius along the tangent (YarnTwist::ply_rate x R)
    float stretch = 1;   // YarnTwist::ply_stretch
};

struct PlyCrossings {
    float own = 0;   // yarn radii inside the ply that was hit
    int others = 0;  // further plies crossed
    float other[kMaxCrossedPlies] = {};  // yarn radii inside each of them (first `others`)
    // The same along the kSpreadDirections spread directions (through a straight tube), filled
    // on demand by add_spread from where the ray started (only the spread crossing asks).
    bool spread_done = false;
    int spread_others[kSpreadDirections] = {};
    float spread[kSpreadDirections][kMaxCrossedPlies] = {};
    const YarnDescription* yarn = nullptr;  // set by cross_plies: what add_spread needs
    PlySection section{};
    int hit_ply = 0;
    Vec3 direction{};
};

// The section of a hit on ply `ply` at `hit` (m), from the centre-line point of its cross-section.
PlySection ply_section(const CurvePoint& cross_section, const YarnDescription& d, const YarnTwist& twist, int ply,
                       Vec3 hit);

// `direction` unit; `chord` yarn radii from the hit to the tube exit along it.
PlyCrossings cross_plies(const PlySection& section, const YarnDescription& d, int hit_ply, Vec3 direction,
                         float chord);

// Fills the spread directions of crossings made by cross_plies (once; nothing without a yarn).
void add_spread(PlyCrossings& plies);

}  // namespace purl
