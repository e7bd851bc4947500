// Stand-in materials until the BYSDF is wired in, and the Lambertian used for meshes.
// Both are one-sided: local normal +z, wo and wi point away from the surface and must
// both have z > 0 (a two-sided surface is the renderer's job: it flips the frame). Surfaces:
// the exit (bsdf/scatter_exit.h) does not matter to them.
//
// PlaceholderYarnBsdf: colour/pi diffuse plus isotropic GGX reflection, mixed by a
// Schlick-style Fresnel weight F = specular * (0.04 + 0.96 (1 - cos theta_o)^5) taken at
// the viewing direction:   f = F * D G2 / (4 cos_o cos_i) + (1 - F) * colour / pi.
// The microfacet part alone reflects at most 1, so the sum never exceeds 1 for colour <= 1
// (at the price of reciprocity, which a placeholder does not need).
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "bsdf/bsdf_sample.h"
#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "base/param_info.h"
#include "bsdf/scatter_exit.h"
#include "math/sampling.h"

namespace purl {

struct DiffuseBsdf {
    Vec3 albedo{0.8f};  // hemispherical reflectance, linear Rec.709, each in [0, 1]

    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const {
        return (wo.z > 0 && wi.z > 0) ? albedo * kInvPi : Vec3(0.0f);
    }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return {eval(wo, wi), pdf(wo, wi)}; }
    std::optional<BsdfSample> sample(Vec3 wo, float /*u_lobe*/, Vec2 u, ExitQuery* = nullptr) const {
        if (!(wo.z > 0)) return std::nullopt;
        BsdfSample s;
        s.wi = sample_cosine_hemisphere(u);
        s.pdf = cosine_hemisphere_pdf(s.wi.z);
        if (!(s.pdf > 0)) return std::nullopt;
        s.f = albedo * kInvPi;
        s.flags = kBsdfReflection | kBsdfBody;
        s.lobe = 0;
        return s;
    }
    float pdf(Vec3 wo, Vec3 wi) const {
        return (wo.z > 0 && wi.z > 0) ? cosine_hemisphere_pdf(wi.z) : 0.0f;
    }
};

struct PlaceholderYarnBsdf {
    Vec3 color{0.8f};        // diffuse albedo, linear Rec.709, each in [0, 1]
    float roughness = 0.3f;  // perceptual GGX roughness in [0, 1]; alpha = roughness^2
    float specular = 0.5f;   // scales the Fresnel weight, in [0, 1]

    enum Lobe { kDiffuse = 0, kGlossy = 1 };

    Ggx ggx() const {
        const float a = std::max(1e-3f, roughness * roughness);
        return {a, a};
    }
    float glossy_weight(Vec3 wo) const {
        return clamp(specular, 0.0f, 1.0f) * fresnel_schlick(0.04f, wo.z);
    }
    // Probability of sampling the glossy lobe: its share of the reflected energy.
    float glossy_probability(Vec3 wo) const {
        const float w = glossy_weight(wo);
        const float diffuse = (1.0f - w) * std::max(0.0f, average(color));
        return w + diffuse > 0 ? w / (w + diffuse) : 0.0f;
    }

    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const {
        if (!(wo.z > 0 && wi.z > 0)) return Vec3(0.0f);
        const float w = glossy_weight(wo);
        Vec3 f = color * ((1.0f - w) * kInvPi);
        const Vec3 h_sum = wo + wi;
        const float len2 = length_squared(h_sum);
        if (len2 > 0) {
            const Vec3 h = h_sum / std::sqrt(len2);
            const Ggx g = ggx();
            f += Vec3(w * g.d(h) * g.g2(wo, wi) / (4 * wo.z * wi.z));
        }
        return f;
    }
    float pdf(Vec3 wo, Vec3 wi) const {
        if (!(wo.z > 0 && wi.z > 0)) return 0.0f;
        const float p_glossy = glossy_probability(wo);
        float p = (1.0f - p_glossy) * cosine_hemisphere_pdf(wi.z);
        const Vec3 h_sum = wo + wi;
        const float len2 = length_squared(h_sum);
        if (len2 > 0 && p_glossy > 0) {
            const Vec3 h = h_sum / std::sqrt(len2);
            const float cos_oh = dot(wo, h);
            if (cos_oh > 0) p += p_glossy * ggx().visible_normal_pdf(wo, h) / (4 * cos_oh);
        }
        return p;
    }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return {eval(wo, wi), pdf(wo, wi)}; }
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* = nullptr) const {
        if (!(wo.z > 0)) return std::nullopt;
        const float p_glossy = glossy_probability(wo);
        if (!(p_glossy > 0) && !(average(color) > 0)) return std::nullopt;
        BsdfSample s;
        if (u_lobe < p_glossy) {
            const Vec3 h = ggx().sample_visible_normal(wo, u);
            s.wi = reflect(wo, h);
            if (!(s.wi.z > 0)) return std::nullopt;  // reflected below the surface
            s.flags = kBsdfReflection | kBsdfSpecular;
            s.lobe = kGlossy;
        } else {
            s.wi = sample_cosine_hemisphere(u);
            s.flags = kBsdfReflection | kBsdfBody;
            s.lobe = kDiffuse;
        }
        s.pdf = pdf(wo, s.wi);
        if (!(s.pdf > 0)) return std::nullopt;
        s.f = eval(wo, s.wi);
        return s;
    }
    // Path regularisation (render/path_regularization.h): alpha = roughness^2 at least `min_alpha`.
    void roughen(float min_alpha) { roughness = std::max(roughness, std::sqrt(min_alpha)); }
};

// The placeholder's parameters as the scene stores them, declared once below.
// Vec3 holds three contiguous floats, so the table's float offsets apply to it.
struct PlaceholderParams {
    Vec3 color;
    float roughness;
    float specular;
};

inline const std::vector<ParamInfo>& placeholder_param_table() {
    static const std::vector<ParamInfo> table = {
        {"color", "", 3, 0.0f, 1.0f, {0.8f, 0.8f, 0.8f},
         "Diffuse albedo of the yarn (linear Rec.709).", offsetof(PlaceholderParams, color), true},
        {"roughness", "", 1, 0.0f, 1.0f, {0.3f, 0, 0},
         "Perceptual GGX roughness of the glossy reflection (alpha = roughness squared).",
         offsetof(PlaceholderParams, roughness), false},
        {"specular", "", 1, 0.0f, 1.0f, {0.5f, 0, 0},
         "Strength of the Fresnel-weighted glossy reflection.", offsetof(PlaceholderParams, specular),
         false},
    };
    return table;
}

inline PlaceholderYarnBsdf make_placeholder_bsdf(const PlaceholderParams& p) {
    return {p.color, p.roughness, p.specular};
}

}  // namespace purl
