// Ply centre-lines as helices around the yarn centre-line, in the curve's rotation-minimizing
// frame: ply i sits at distance ply_distance * R and angle 2 pi i / N + ply_rate * s, where s
// is the arc length v_yarn. Shared by the implicit plies and the explicit reference, so the two
// describe exactly the same yarn.
#pragma once
#include <cstdint>

#include "yarn/curve_frames.h"
#include "yarn/yarn_description.h"

namespace purl {

// Twist rates of one description on one curve. Twist is per yarn radius, so the curve's
// reference radius turns it into radians per metre. On closed loops the rates are rounded so
// that plies, fibers and migration cells all come back to themselves at the seam.
struct YarnTwist {
    float ply_rate = 0;        // rad per m of yarn length, signed by handedness
    float fiber_rate = 0;      // rad per m of ply length, signed by handedness
    float ply_stretch = 1;     // ply length per yarn length: sqrt(1 + (ply_distance R ply_rate)^2)
    float migration_cell = 1;  // m of ply length over which one fiber-map variant blends into the next
    uint32_t migration_cells_per_loop = 0;  // closed loops: cells in one turn of the loop; 0 when open
};

YarnTwist yarn_twist(const CurveFrames& frames, const YarnDescription& d);

struct PlyCentre {
    Vec3 position;    // m
    Vec3 derivative;  // dP/ds, per m of yarn length (not unit; exact for a rotation-minimizing frame)
    Vec3 second_derivative;  // d2P/ds2, 1/m (neglecting how the curvature itself changes)
    Vec3 outward;     // unit, from the yarn centre-line toward the ply centre-line
    float phase;      // angle around the yarn from the reference normal, rad
    float radius;     // ply radius, m
};

// Angle of ply 0 around the yarn at arc length s (rad, not wrapped).
inline float ply_phase(const YarnTwist& twist, float arc_length) { return twist.ply_rate * arc_length; }

PlyCentre ply_centre(const CurvePoint& yarn, const YarnDescription& d, const YarnTwist& twist, int ply);
// The same for a phase whose cosine and sine the caller already has (e.g. one turn of the
// yarn's phase shared by all plies, combined with each ply's fixed offset).
PlyCentre ply_centre(const CurvePoint& yarn, const YarnDescription& d, const YarnTwist& twist, float phase,
                     float cos_phase, float sin_phase);

}  // namespace purl
