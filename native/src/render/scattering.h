// Every scattering model behind one interface, so the path tracer never names a model. All
// work in a local frame (wo toward the viewer, wi toward the light, both pointing away):
//
//   eval_pdf(wo, wi, exit)       f (1/sr, without the cosine) and the density of `sample` at wi,
//                                in one evaluation: what next-event estimation needs
//   eval(wo, wi, exit), pdf(wo, wi)   either alone (tests, diagnostics)
//   sample(wo, u_lobe, u, exit)  a direction with its final f and pdf; `exit` (bsdf/scatter_exit.h)
//                                is asked for the sampled direction's exit before the model
//                                evaluates it, so nothing is evaluated twice
//   roughen(min_alpha)           path regularisation, for the models that have glossy lobes
//
// The exit is the small context that differs between models: the chord through the yarn and,
// with traced ply crossing, the plies crossed. The BYSDF attenuates by it; surfaces, the fiber
// BCSDF, the multi-scale mixture and the tabulated far field do not need it.
#pragma once
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

#include "bsdf/bsdf_sample.h"
#include "bsdf/bysdf.h"
#include "bsdf/fiber_bcsdf.h"
#include "bsdf/placeholder.h"
#include "bsdf/scatter_exit.h"
#include "render/far_field.h"
#include "render/multiscale.h"

namespace purl {

namespace scattering_detail {
template <class M, class = void>
constexpr bool kRoughens = false;
template <class M>
constexpr bool kRoughens<M, std::void_t<decltype(std::declval<M&>().roughen(0.0f))>> = true;
}  // namespace scattering_detail

class Scattering {
public:
    using Model = std::variant<DiffuseBsdf, PlaceholderYarnBsdf, Bysdf, FiberBcsdfRef, MultiscaleBysdf, FarFieldBsdf>;

    Scattering() = default;
    template <class M, class = std::enable_if_t<std::is_constructible_v<Model, M&&>>>
    Scattering(M&& model) : model_(std::forward<M>(model)) {}  // NOLINT: a model is a Scattering

    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& exit) const {
        return std::visit([&](const auto& m) { return m.eval_pdf(wo, wi, exit); }, model_);
    }
    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& exit) const {
        return std::visit([&](const auto& m) { return m.eval(wo, wi, exit); }, model_);
    }
    float pdf(Vec3 wo, Vec3 wi) const {
        return std::visit([&](const auto& m) { return m.pdf(wo, wi); }, model_);
    }
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* exit) const {
        return std::visit([&](const auto& m) { return m.sample(wo, u_lobe, u, exit); }, model_);
    }
    // Raises the glossy lobes' GGX alpha to at least `min_alpha`. Diffuse surfaces have none;
    // the fiber reference stays exact (it is a reference); the multi-scale and far-field models
    // shade camera hits only, which are never regularised.
    void roughen(float min_alpha) {
        std::visit(
            [&](auto& m) {
                if constexpr (scattering_detail::kRoughens<std::decay_t<decltype(m)>>) m.roughen(min_alpha);
            },
            model_);
    }

    // Per-model features outside the interface (the denoiser's albedo, tests).
    template <class Visitor>
    decltype(auto) visit(Visitor&& v) const {
        return std::visit(std::forward<Visitor>(v), model_);
    }
    template <class M>
    const M* get_if() const {
        return std::get_if<M>(&model_);
    }

private:
    Model model_;
};

}  // namespace purl
