#include "yarn/yarn_shading_point.h"

#include <cmath>

#include "math/rng.h"
#include "yarn/ply_helix.h"

namespace purl {

namespace {

YarnShadingPoint shade(const PlyHit& hit, const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw,
                       const FiberMaps& maps, uint32_t curve_key) {
    YarnShadingPoint sp;
    sp.segment = hit.segment;
    sp.t = hit.t;
    sp.exit_distance = hit.exit_distance;
    if (!hit.hit) {
        sp.position = hit.point;
        return sp;
    }
    sp.hit = true;
    sp.position = hit.point;
    sp.ply_normal = hit.normal;
    sp.ply_tangent = hit.tangent;
    sp.ply_index = hit.ply;
    sp.plies_crossed = hit.plies_crossed;
    sp.u_ply = hit.u_ply;
    sp.v_ply = hit.v_ply;
    sp.u_yarn = hit.u_yarn;
    sp.v_yarn = hit.v_yarn;
    sp.distance = hit.distance;
    sp.ply_shadowing = maps.ply_shadowing(hit.arrangement_azimuth);

    // Fibers turn around the ply at fiber_rate per metre of ply: the map frame lags behind.
    const float turned = tw.fiber_rate * hit.v_ply;
    const uint32_t key = static_cast<uint32_t>(mix64((uint64_t(curve_key) << 8) | uint32_t(hit.ply)));
    const FiberSample f =
        maps.lookup(hit.u_ply - turned, hit.v_ply / tw.migration_cell, key, tw.migration_cells_per_loop);
    sp.fiber_shadowing = f.shadowing;

    // n' : the visible fiber's normal, rotated from the ply normal about the ply tangent.
    const Vec3 t = hit.tangent, n = hit.normal;
    Vec3 normal = n * std::cos(f.normal_angle) + cross(t, n) * std::sin(f.normal_angle);
    // R : that fiber's helix leans toward its own azimuthal direction around the ply.
    const Vec3 side = cross(t, hit.outward);
    const float at = f.fiber_phase + turned;
    const Vec3 around = side * std::cos(at) - hit.outward * std::sin(at);
    const float ply_radius = d.ply_radius * frames.reference_radius();
    Vec3 tangent = normalize(t + around * (tw.fiber_rate * f.fiber_distance * ply_radius));
    normal -= tangent * dot(normal, tangent);
    const float len = length(normal);
    sp.fiber_normal = len > 1e-6f ? normal / len : n;
    sp.fiber_tangent = tangent;
    if (!is_finite(sp.fiber_normal) || !is_finite(sp.fiber_tangent)) {
        sp.fiber_normal = n;  // cannot happen with finite input; keep the frame defined anyway
        sp.fiber_tangent = t;
    }
    return sp;
}

}  // namespace

YarnShadingPoint shade_ply_hit(const PlyHit& hit, const CurveFrames& frames, const YarnDescription& d,
                               const FiberMaps& maps, uint32_t curve_key) {
    return shade(hit, frames, d, yarn_twist(frames, d), maps, curve_key);
}

YarnShadingPoint shade_ply_hit(const PlyHit& hit, const CurveFrames& frames, const YarnDescription& d,
                               const YarnTwist& twist, const FiberMaps& maps, uint32_t curve_key) {
    return shade(hit, frames, d, twist, maps, curve_key);
}

YarnShadingPoint trace_yarn_hit(const CurveFrames& frames, const YarnDescription& d, const FiberMaps& maps,
                                const YarnTubeHit& hit, uint32_t curve_key, const PlyTraceOptions& options) {
    return trace_yarn_hit(frames, d, yarn_twist(frames, d), maps, hit, curve_key, options);
}

YarnShadingPoint trace_yarn_hit(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& twist,
                                const FiberMaps& maps, const YarnTubeHit& hit, uint32_t curve_key,
                                const PlyTraceOptions& options) {
    return shade(trace_plies({frames, d, twist, hit}, options), frames, d, twist, maps, curve_key);
}

}  // namespace purl
