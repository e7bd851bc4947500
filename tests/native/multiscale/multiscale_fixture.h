// A straight yarn of radius 1 along +z (the yarn suite's validation curve) with the default
// description, maps and BYSDF, and camera-like rays from +x tilted by psi toward +z, given by
// their offset y across the yarn. One-pixel differentials are parallel rays `width` radii
// apart across the yarn (and one along it, which must not count).
#pragma once
#include <cmath>
#include <vector>

#include "bsdf/bysdf_params.h"
#include "render/multiscale.h"
#include "yarn/ply_crossings.h"
#include "yarn/straight_yarn.h"
#include "yarn/yarn_shading_point.h"

namespace purl::test {

struct StraightYarn {
    std::vector<Vec4> points = straight_yarn_points();
    CurveFrames frames{CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), false)};
    YarnDescription description = default_yarn_description();
    FiberMaps maps{description};
    BysdfParams params = default_bysdf_params();
    // Every h sample a footprint allows (the renderer's default caps them at 5): the tests
    // check the footprint integral itself.
    MultiscaleSettings settings = all_h_samples();

    static MultiscaleSettings all_h_samples() {
        MultiscaleSettings s = default_multiscale_settings();
        s.max_h_samples = float(kMaxHSamples);
        return s;
    }

    MultiscaleYarn yarn() const { return {&frames, &description, &maps, &params, 7, Vec3(1.0f), {}}; }

    static Vec3 direction(float psi) { return normalize(Vec3(-std::cos(psi), 0.0f, std::sin(psi))); }

    // The ray at offset y (|y| < 1) across the yarn, entering the tube at height z.
    YarnTubeHit tube_hit(float y, float psi, float z) const {
        YarnTubeHit h;
        h.direction = direction(psi);
        h.point = Vec3(std::sqrt(1 - y * y), y, z);
        h.origin = h.point - h.direction * 5.0f;
        const CentrelineProjection p = project_to_centreline(frames, h.point, static_cast<uint32_t>(z) - 1, 0.5f);
        h.segment = p.segment;
        h.t = p.t;
        return h;
    }

    // The ray of tube_hit(y0, psi, z0) moved sideways to offset y: it enters the tube elsewhere
    // along the yarn when psi != 0.
    YarnTubeHit shifted_hit(float y0, float y, float psi, float z0) const {
        return tube_hit(y, psi, z0 + (std::sqrt(1 - y0 * y0) - std::sqrt(1 - y * y)) * std::tan(psi));
    }

    Ray camera_ray(const YarnTubeHit& h, float width) const {
        Ray r;
        r.origin = h.origin;
        r.direction = h.direction;
        r.has_differentials = width > 0;
        r.rx_origin = h.origin + Vec3(0, width, 0);  // across: dh = width
        r.rx_direction = h.direction;
        const Vec3 along = cross(h.direction, Vec3(0, 1, 0));
        r.ry_origin = h.origin + along * 0.37f;  // along the yarn: dh = 0
        r.ry_direction = h.direction;
        return r;
    }

    MultiscaleQuery query(float y, float psi, float z, float width, MultiscaleMode mode, float u) const {
        return query_at(tube_hit(y, psi, z), width, mode, u);
    }
    MultiscaleQuery query_at(const YarnTubeHit& tube, float width, MultiscaleMode mode, float u) const {
        MultiscaleQuery q;
        q.tube = tube;
        q.axis = project_to_centreline(frames, q.tube.point, q.tube.segment, q.tube.t);
        q.footprint = yarn_footprint(camera_ray(q.tube, width), q.tube.point, q.axis.point, 1.0f);
        q.mode = mode;
        q.u_strata = u;
        return q;
    }
};

// f |cos| (world directions) of the plain near-field BYSDF at one tube hit, attenuated along
// the exact tube chord: the renderer's near-field path, written out independently.
// `roughening` is added to the three specular roughnesses. Zero where the ray passes through.
inline Vec3 near_field_integrand(const StraightYarn& s, const YarnTubeHit& hit, Vec3 wo, Vec3 wi,
                                 float roughening = 0.0f) {
    const YarnShadingPoint y = trace_yarn_hit(s.frames, s.description, s.maps, hit, 7);
    if (!y.hit) return Vec3(0.0f);
    BysdfParams p = s.params;
    p.specular_roughness_along += roughening;
    p.specular_roughness_across += roughening;
    p.transmission_roughness += roughening;
    const Bysdf b(p, BysdfShadingPoint{y.ply_shadowing, y.fiber_shadowing, std::max(1, y.plies_crossed), y.ply_index,
                                       Vec3(1.0f), s.maps.mean_fiber_shadowing()});
    const Frame f = Frame::from_normal_tangent(y.fiber_normal, y.fiber_tangent);
    const Vec3 wo_l = f.to_local(wo), wi_l = f.to_local(wi);
    const float radius = s.frames.reference_radius();
    if (b.traces_plies()) {  // as ShadingPoint::leave: the plies the leaving ray crosses
        const float chord = tube_chord_length(s.frames, y.segment, y.t, y.position, wi) / radius;
        const PlySection section = ply_section(s.frames.evaluate(y.segment, y.t), s.description,
                                               yarn_twist(s.frames, s.description), y.ply_index, y.position);
        const PlyCrossings plies = cross_plies(section, s.description, y.ply_index, wi, chord);
        return b.eval(wo_l, wi_l, {chord, &plies}) * std::fabs(wi_l.z);
    }
    const float chord = wo_l.z * wi_l.z < 0 ? tube_chord_length(s.frames, y.segment, y.t, y.position, wi) : 0.0f;
    return b.eval(wo_l, wi_l, {chord / radius}) * std::fabs(wi_l.z);
}

// The model's f~ |cos_ref| for world directions, times the share of the footprint that hit.
inline Vec3 model_integrand(const MultiscaleBysdf& m, Vec3 wo, Vec3 wi) {
    if (m.empty()) return Vec3(0.0f);
    const Vec3 wi_l = m.frame().to_local(wi);
    return m.eval(m.frame().to_local(wo), wi_l) * (std::fabs(wi_l.z) * (1.0f - m.pass_fraction()));
}

}  // namespace purl::test
