// The circular method (Zhu et al. 2023, the prototype): plies frozen in the perpendicular
// cross-section at the tube hit, the ray projected into it. For comparison, for bounce rays
// whose cone spans a ply (render/shading.cpp), and the exact method's fallback for a ply
// whose crossing does not converge. In a header: small, and a call
// into another file cost it 0.4 % more instructions.
#pragma once
#include <algorithm>
#include <cmath>

#include "yarn/plies/result.h"

namespace purl::plies {

// The circular method's hit on one ply: the ray projected into the perpendicular cross-section
// at `at`, against the ply's circle there. `enter` is the matching distance along the 3D ray;
// false when the projected ray misses the circle.
inline bool circular_cut_hit(const YarnTubeHit& hit, const CentrelineProjection& at, const PlyCentre& centre,
                             float& enter, Vec3& normal) {
    const Vec3 tangent = at.point.tangent;
    Vec3 flat = hit.direction - tangent * dot(hit.direction, tangent);
    const float flat_length = length(flat);
    if (flat_length < 1e-4f) return false;
    flat = flat / flat_length;
    const Vec3 x0 = hit.point - tangent * dot(hit.point - at.point.position, tangent);
    const Vec3 w = x0 - centre.position;
    const float b = dot(w, flat), c = dot(w, w) - sqr(centre.radius);
    const float disc = b * b - c;
    if (disc < 0) return false;
    const float root = std::sqrt(disc);
    if (-b + root <= 0) return false;
    const float along = std::max(-b - root, 0.0f);
    enter = along / flat_length;
    normal = normalize(w + flat * along);
    return true;
}

// The method: `at` is the projection of the tube entry, with its frame.
[[gnu::always_inline]] inline PlyHit trace_circular(const PlyQuery& q, const CentrelineProjection& at) {
    const YarnTubeHit& hit = q.ray;
    Candidate best;
    bool found = false;
    int crossed = 0;
    Vec3 best_normal;
    for (int ply = 0; ply < q.yarn.plies(); ++ply) {
        const PlyCut cut = cut_at(at, q.yarn, q.twist, ply);
        float enter;
        Vec3 normal;
        if (!circular_cut_hit(hit, at, cut.centre, enter, normal)) continue;
        ++crossed;
        if (found && enter >= best.enter) continue;
        found = true;
        best.ply = ply;
        best.cut = cut;
        best.enter = enter;
        best_normal = normal;
    }
    if (!found) return pass_through(q.frames, hit, at);
    PlyHit h = finish_hit(best, hit.point + hit.direction * best.enter, q.twist, hit);
    // The circular method's normal is the 2D one, in the frozen cross-section.
    h.normal = best_normal;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.plies_crossed = crossed;
    return h;
}

}  // namespace purl::plies
