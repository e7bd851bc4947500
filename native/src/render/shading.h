// Turns a surface hit into a scattering model in a local frame. The integrator only sees
// eval / sample / pdf, whichever model a surface has.
#pragma once
#include <optional>
#include <variant>

#include "bsdf/placeholder.h"
#include "math/frame.h"
#include "scene/embree_scene.h"
#include "scene/scene.h"

namespace purl {

using SurfaceBsdf = std::variant<DiffuseBsdf, PlaceholderYarnBsdf>;

struct ShadingPoint {
    Frame frame;          // world <-> local; local +z is the shading normal, facing the viewer
    SurfaceBsdf bsdf;
    bool holdout = false;

    Vec3 eval(Vec3 wo_world, Vec3 wi_world) const {
        const Vec3 wo = frame.to_local(wo_world), wi = frame.to_local(wi_world);
        return std::visit([&](const auto& b) { return b.eval(wo, wi); }, bsdf);
    }
    float pdf(Vec3 wo_world, Vec3 wi_world) const {
        const Vec3 wo = frame.to_local(wo_world), wi = frame.to_local(wi_world);
        return std::visit([&](const auto& b) { return b.pdf(wo, wi); }, bsdf);
    }
    std::optional<BsdfSample> sample(Vec3 wo_world, float u_lobe, Vec2 u) const {
        const Vec3 wo = frame.to_local(wo_world);
        auto s = std::visit([&](const auto& b) { return b.sample(wo, u_lobe, u); }, bsdf);
        if (s) s->wi = frame.to_world(s->wi);
        return s;
    }
};

// `wo` points from the hit back toward where the ray came from.
ShadingPoint make_shading_point(const SceneDesc& scene, const SurfaceHit& hit, Vec3 wo);

}  // namespace purl
