// The structure of one kind of yarn: plies twisted around the yarn centre-line and fibers
// twisted around each ply centre-line, after the procedural model of Zhao, Luan and Bala 2016
// ("Fitting procedural yarn models"), as Khattar et al. 2024 (section 3) use it implicitly.
//
// Lengths are relative so a description does not change with scene scale:
//   ply_radius, ply_distance  in yarn radii R (R = the curve's radius at the hit);
//   fiber_radius              in ply radii;
//   ply_twist, fiber_twist    in radians per yarn radius of length (pitch = 2 pi R / twist).
// Every field is declared once in yarn_description_params() (name, unit, range, default,
// meaning); JSON, Python and the Blender UI derive from that table. Integer-valued fields are
// floats there (the table addresses floats) and must hold whole numbers.
#pragma once
#include <string>
#include <vector>

#include "base/param_info.h"

namespace purl {

constexpr int kMaxPlies = 12;

struct YarnDescription {
    float ply_count;            // plies in the yarn, whole number 1..12
    float ply_radius;           // ply radius, yarn radii
    float ply_distance;         // ply centre-line to yarn centre-line, yarn radii
    float ply_twist;            // ply turn rate around the yarn, rad per yarn radius of yarn length
    float ply_handedness;       // +1 Z twist (right-handed helix), -1 S twist
    float fiber_count;          // fibers per ply, whole number
    float fiber_radius;         // fiber radius, ply radii
    float fiber_twist;          // fiber turn rate around the ply, rad per yarn radius of ply length
    float fiber_handedness;     // +1 Z, -1 S (usually opposite to the plies)
    float migration_rho_min;    // smallest fiber distance from the ply centre, fraction of its rest distance
    float migration_rho_max;    // largest fiber distance, fraction of its rest distance
    float migration_frequency;  // s_i: migration cycles per fiber turn
    float density_eps;          // Zhao's eps: relative fiber density at the ply boundary
    float density_beta;         // Zhao's beta: how fast the density falls toward the boundary
    float map_resolution;       // samples around the circumference in each 1D map, whole number
    float migration_variants;   // fiber maps switched along a ply to imitate migration, whole number
    float seed;                 // seed of the procedural cross-sections, whole number

    int plies() const { return static_cast<int>(ply_count); }
    int fibers() const { return static_cast<int>(fiber_count); }
    int resolution() const { return static_cast<int>(map_resolution); }
    int variants() const { return static_cast<int>(migration_variants); }
};

const std::vector<ParamInfo>& yarn_description_params();

// The table's defaults: the authors' prototype (3 plies of radius 0.45 R touching at
// distance r / sin(pi/3), 1/3 rad per unit at R = 2, 25 fibers of radius 1/sqrt(50)).
YarnDescription default_yarn_description();

// "prototype" or one of Zhao et al.'s fitted sets "A" .. "I" (REFERENCE.md section 2),
// converted to relative units (see docs/implicit-geometry.md). Throws InputError for other names.
YarnDescription yarn_preset(const std::string& name);
std::vector<std::string> yarn_preset_names();

// Throws InputError(file, place + "." + field, reason) for a NaN, out-of-range or
// non-integer field, or for plies that do not fit inside the yarn tube.
void check_yarn_description(const YarnDescription& d, const std::string& file, const std::string& place);

}  // namespace purl
