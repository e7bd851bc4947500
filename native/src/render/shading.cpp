#include "render/shading.h"

#include <cmath>
#include <limits>

#include "yarn/yarn_shading_point.h"
#include "yarn/yarn_tube.h"

namespace purl {

float ray_offset(Vec3 p, float yarn_radius) {
    const float m = std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z)));
    return 64.0f * std::numeric_limits<float>::epsilon() * m + 1e-2f * yarn_radius;
}

ShadingPoint::Exit ShadingPoint::leave(Vec3 wi) const {
    if (tube) {
        const float chord = tube_chord_length(*tube, segment, t, position, wi);
        return {position + wi * (chord + ray_offset(position, yarn_radius)), chord / yarn_radius};
    }
    const float side = dot(surface_normal, wi) >= 0 ? offset : -offset;
    return {position + surface_normal * side, 0.0f};
}

Vec3 ShadingPoint::eval(Vec3 wo_world, Vec3 wi_world, float chord) const {
    const Vec3 wo = frame.to_local(wo_world), wi = frame.to_local(wi_world);
    if (const Bysdf* b = std::get_if<Bysdf>(&bsdf)) return b->eval(wo, wi, chord);
    return std::visit([&](const auto& model) { return model.eval(wo, wi); }, bsdf);
}

float ShadingPoint::pdf(Vec3 wo_world, Vec3 wi_world) const {
    const Vec3 wo = frame.to_local(wo_world), wi = frame.to_local(wi_world);
    return std::visit([&](const auto& model) { return model.pdf(wo, wi); }, bsdf);
}

std::optional<BsdfSample> ShadingPoint::sample(Vec3 wo_world, float u_lobe, Vec2 u, Exit& exit) const {
    const Vec3 wo = frame.to_local(wo_world);
    std::optional<BsdfSample> s = std::visit([&](const auto& model) { return model.sample(wo, u_lobe, u); }, bsdf);
    if (!s) return s;
    const Vec3 wi_local = s->wi;
    s->wi = frame.to_world(wi_local);
    exit = leave(s->wi);
    // The BYSDF samples without knowing the path through the yarn; attenuate now.
    if (const Bysdf* b = std::get_if<Bysdf>(&bsdf); b && s->is_transmission())
        s->f = b->eval(wo, wi_local, exit.chord);
    return s;
}

SurfaceShader::SurfaceShader(const SceneDesc& scene) : scene_(scene) {
    uint32_t key = 0;
    for (const YarnSetDesc& set : scene.yarns) {
        curve_key_base_.push_back(key);
        key += static_cast<uint32_t>(set.curves.curve_count());
        YarnSetData data;
        if (set.material.model == "bysdf") {
            const YarnCurves& c = set.curves;
            data.frames.reserve(c.curve_count());
            for (size_t i = 0; i < c.curve_count(); ++i) {
                // Segment indices are global, so the view's base is the set's first point.
                const uint32_t first_segment = c.segment_offsets[i];
                data.frames.emplace_back(CurveView::separate_segments(
                    c.control_points.data(), static_cast<uint32_t>(c.point_count()),
                    c.segment_first.data() + first_segment, c.segment_count(i), c.closed[i] != 0));
            }
            data.maps = std::make_unique<FiberMaps>(set.material.yarn);
        }
        yarn_sets_.push_back(std::move(data));
    }
}

SurfaceShader::~SurfaceShader() = default;

size_t SurfaceShader::memory_bytes() const {
    size_t bytes = 0;
    for (const YarnSetData& d : yarn_sets_) {
        for (const CurveFrames& f : d.frames) bytes += f.memory_bytes();
        if (d.maps) bytes += d.maps->memory_bytes();
    }
    return bytes;
}

SurfaceInteraction SurfaceShader::shade(const SurfaceHit& hit, const Ray& ray) const {
    SurfaceInteraction out;
    ShadingPoint& sp = out.point;
    const Vec3 wo = -ray.direction;
    // Surfaces are shaded two-sided: the normal faces the viewer.
    const Vec3 n = dot(hit.geometric_normal, wo) >= 0 ? hit.geometric_normal : -hit.geometric_normal;
    sp.position = hit.position;
    sp.surface_normal = n;
    sp.offset = ray_offset(hit.position, hit.radius);
    if (hit.kind == SurfaceKind::Mesh) {
        const MeshDesc& mesh = scene_.meshes[hit.object];
        sp.frame = Frame::from_normal(n);
        sp.bsdf = DiffuseBsdf{mesh.color};
        sp.holdout = mesh.holdout;
        return out;
    }
    const MaterialDesc& m = scene_.yarns[hit.object].material;
    if (m.model == "placeholder") {
        sp.frame = Frame::from_normal_tangent(n, hit.tangent);
        sp.bsdf = make_placeholder_bsdf(m.placeholder);
        return out;
    }
    // BYSDF: find the ply and fiber under the tube hit.
    const YarnSetData& data = yarn_sets_[hit.object];
    const CurveFrames& frames = data.frames[hit.curve];
    YarnTubeHit tube_hit{ray.origin, ray.direction, hit.position, hit.segment, hit.u};
    const YarnShadingPoint y = trace_yarn_hit(frames, m.yarn, *data.maps, tube_hit, curve_key_base_[hit.object] + hit.curve);
    if (!y.hit) {
        out.pass_through = true;
        out.continue_distance = y.exit_distance;
        return out;
    }
    sp.position = y.position;
    sp.frame = Frame::from_normal_tangent(y.fiber_normal, y.fiber_tangent);
    sp.tube = &frames;
    sp.segment = hit.segment;
    sp.t = hit.u;
    sp.yarn_radius = hit.radius;
    BysdfShadingPoint bp;
    bp.ply_shadow = y.ply_shadowing;
    bp.fiber_shadow = y.fiber_shadowing;
    bp.plies_crossed = std::max(1, y.plies_crossed);
    bp.ply_index = y.ply_index;
    sp.bsdf = Bysdf(m.bysdf, bp);
    return out;
}

}  // namespace purl
