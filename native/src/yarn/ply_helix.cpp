#include "yarn/ply_helix.h"

#include <algorithm>
#include <cmath>

namespace purl {

YarnTwist yarn_twist(const CurveFrames& frames, const YarnDescription& d) {
    YarnTwist tw;
    const float radius = std::max(frames.reference_radius(), 1e-30f);
    const float length = frames.total_length();
    const bool loop = frames.closed() && length > 0;
    tw.ply_rate = d.ply_handedness * d.ply_twist / radius;
    // Each ply must come back to itself around a loop (a ply's colour must not change at
    // the seam), so loops hold a whole number of ply turns.
    if (loop) tw.ply_rate = std::round(tw.ply_rate * length / (2 * kPi)) * 2 * kPi / length;
    tw.ply_stretch = std::sqrt(1 + sqr(d.ply_distance * radius * tw.ply_rate));

    const float ply_length = length * tw.ply_stretch;
    tw.fiber_rate = d.fiber_handedness * d.fiber_twist / radius;
    if (loop) tw.fiber_rate = std::round(tw.fiber_rate * ply_length / (2 * kPi)) * 2 * kPi / ply_length;

    // Half a migration wavelength per cell (a wavelength is one fiber turn / s_i); without
    // migration or twist the variants still switch, every 4 yarn radii.
    const float turn = std::fabs(tw.fiber_rate) > 0 ? 2 * kPi / std::fabs(tw.fiber_rate) : 0.0f;
    tw.migration_cell = turn > 0 && d.migration_frequency > 0 ? 0.5f * turn / d.migration_frequency : 4 * radius;
    tw.migration_cell = clamp(tw.migration_cell, 0.5f * radius, 100 * radius);
    if (loop) {
        tw.migration_cells_per_loop = static_cast<uint32_t>(std::max(1.0f, std::round(ply_length / tw.migration_cell)));
        tw.migration_cell = ply_length / tw.migration_cells_per_loop;
    }
    return tw;
}

PlyCentre ply_centre(const CurvePoint& yarn, const YarnDescription& d, const YarnTwist& twist, int ply) {
    const int plies = std::max(1, d.plies());
    const float phase = 2 * kPi * ply / plies + ply_phase(twist, yarn.arc_length);
    return ply_centre(yarn, d, twist, phase, std::cos(phase), std::sin(phase));
}

PlyCentre ply_centre(const CurvePoint& yarn, const YarnDescription& d, const YarnTwist& twist, float phase,
                     float c, float s) {
    PlyCentre p;
    p.phase = phase;
    p.outward = yarn.normal * c + yarn.binormal * s;
    const float offset = d.ply_distance * yarn.radius;
    p.position = yarn.position + p.outward * offset;
    p.radius = d.ply_radius * yarn.radius;
    // A rotation-minimizing frame turns only toward the tangent, dN/ds = -(k.N) T; the stored
    // one also turns a little about it (frame_turn), and the phase follows the interpolated
    // arc length (arc_rate): without these, tangents on knitted cloth were 0.3-0.6 deg off.
    const Vec3 around = yarn.binormal * c - yarn.normal * s;
    const float bend = 1 - offset * dot(yarn.curvature, p.outward);
    p.derivative = yarn.tangent * bend + around * (offset * (twist.ply_rate * yarn.arc_rate + yarn.frame_turn));
    p.second_derivative = yarn.curvature * bend - p.outward * (offset * twist.ply_rate * twist.ply_rate) -
                          yarn.tangent * (2 * offset * twist.ply_rate * dot(yarn.curvature, around));
    return p;
}

}  // namespace purl
