#include "yarn/plies/result.h"

#include <algorithm>
#include <cmath>

namespace purl::plies {

void locate(const CachedCurve& frames, double g, uint32_t& segment, float& t) {
    const double n = frames.segment_count();
    if (frames.closed()) {
        if (!(std::fabs(g) < n)) g = std::fmod(g, n);  // fmod would return g as it is
        if (g < 0) g += n;
    } else {
        g = std::min(std::max(g, 0.0), n);
    }
    segment = std::min(static_cast<uint32_t>(g), frames.segment_count() - 1);
    t = static_cast<float>(g - segment);
}

PlyCut cut_at(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply, double g) {
    PlyCut cut;
    cut.g = g;
    locate(frames, g, cut.segment, cut.t);
    cut.yarn = frames.evaluate(cut.segment, cut.t);
    cut.centre = ply_centre(cut.yarn, d, tw, ply);
    return cut;
}

PlyHit finish_hit(const Candidate& c, Vec3 point, const YarnTwist& tw, const YarnTubeHit& hit) {
    PlyHit h;
    h.hit = true;
    h.ply = c.ply;
    h.point = point;
    h.distance = std::max(c.enter, 0.0f);
    h.tangent = normalize(c.cut.centre.derivative);
    Vec3 radial = point - c.cut.centre.position;
    radial -= h.tangent * dot(radial, h.tangent);
    h.outward = c.cut.centre.outward - h.tangent * dot(c.cut.centre.outward, h.tangent);
    h.outward = normalize(h.outward);
    const float len = length(radial);
    // A hit on the ply's axis (only with a degenerate ray) faces the viewer.
    h.normal = len > 1e-12f ? radial / len : normalize(-hit.direction - h.tangent * dot(-hit.direction, h.tangent));
    if (!is_finite(h.normal)) h.normal = h.outward;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.v_ply = c.cut.yarn.arc_length * tw.ply_stretch;
    h.u_yarn = CurveFrames::azimuth(c.cut.yarn, point);
    h.v_yarn = c.cut.yarn.arc_length;
    h.arrangement_azimuth = wrap_angle(h.u_yarn - ply_phase(tw, c.cut.yarn.arc_length));
    h.segment = c.cut.segment;
    h.t = c.cut.t;
    return h;
}

// Out of line: inlined into the methods' entry searches, it pushed their scans out of line
// (+3 % instructions for the local method).
bool cross_ply_cylinder(Vec3 origin, Vec3 direction, Vec3 point, Vec3 axis, float radius, float& enter,
                        float& leave) {
    const RayCylinder r = ray_cylinder(origin, direction, point, axis, radius);
    if (r.along_axis()) {
        if (!(r.c <= 0)) return false;
        enter = 0;
        leave = 1e30f;
        return true;
    }
    if (r.discriminant() < 0) return false;
    enter = r.entry();
    leave = r.exit();
    return leave > 0;
}

PlyHit pass_through(const YarnTubeHit& hit, float exit_distance) {
    PlyHit h;
    h.exit_distance = exit_distance;
    h.point = hit.point + hit.direction * h.exit_distance;
    return h;
}

PlyHit pass_through(const CurveFrames& frames, const YarnTubeHit& hit, uint32_t segment, float t) {
    return pass_through(hit, tube_chord_length(frames, segment, t, hit.point, hit.direction));
}

}  // namespace purl::plies
