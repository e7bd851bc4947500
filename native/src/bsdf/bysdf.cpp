#include "bsdf/bysdf.h"

#include <algorithm>

#include "base/registry.h"
#include "bsdf/fresnel.h"
#include "bsdf/lommel_seeliger.h"
#include "math/sampling.h"

namespace purl {
namespace {

// Directions closer to the tangent plane than this carry no energy: the microfacet and LS
// terms would divide 0 by 0 there, and the band holds ~1e-12 of the cosine-weighted sphere.
constexpr float kMinCos = 1e-6f;
constexpr float kMinAlpha = 1e-3f;  // below this GGX is a mirror in float precision

thread_local uint64_t evaluations = 0;  // bysdf_evaluations_on_this_thread

Vec3 clamp01(Vec3 c) {
    return {clamp(c.x, 0.0f, 1.0f), clamp(c.y, 0.0f, 1.0f), clamp(c.z, 0.0f, 1.0f)};
}
float clamp_alpha(float a) { return clamp(a, kMinAlpha, 1.0f); }
float clamp01(float v) { return v >= 0 ? std::min(v, 1.0f) : 0.0f; }  // NaN -> 0

// Generalised half vector of a refraction from wo (outside, index 1) to wi (inside, index
// eta), on the +z side. False when wo, wi cannot be linked by any microfacet.
bool transmission_half_vector(Vec3 wo, Vec3 wi, float eta, Vec3& h, float& cos_oh, float& cos_ih) {
    Vec3 sum = wo + wi * eta;
    const float len2 = length_squared(sum);
    if (!(len2 > 1e-12f)) return false;
    h = sum / std::sqrt(len2);
    if (h.z < 0) h = -h;
    cos_oh = dot(wo, h);
    cos_ih = dot(wi, h);
    return cos_oh > 0 && cos_ih < 0;
}

}  // namespace

uint64_t bysdf_evaluations_on_this_thread() { return evaluations; }

Bysdf::Bysdf(const BysdfParams& p, const BysdfShadingPoint& point) {
    reflection_ggx_ = {clamp_alpha(p.specular_roughness_along), clamp_alpha(p.specular_roughness_across)};
    transmission_ggx_ = {clamp_alpha(p.transmission_roughness), clamp_alpha(p.transmission_roughness)};
    eta_ = clamp(p.eta, kFiberEta.min, kFiberEta.max);  // the table's range (base/registry.h)
    if (!(eta_ > 0)) eta_ = 1.5f;  // NaN

    const float body = clamp01(p.body_share);
    k_spec_r_ = clamp01(p.specular_reflection_albedo) * (1.0f - body);
    k_spec_t_ = clamp01(p.specular_transmission_albedo) * (1.0f - body);

    // Shadowing dims only the body lobes, as in the paper; floors keep plies from going black.
    // Traced ply crossing: the plies that shadow x are crossed by the ray itself, so no G_p.
    traced_ = p.ply_crossing >= 0.5f;
    spread_ = p.ply_crossing >= 1.5f;
    const float fiber_shadow = std::max(clamp01(point.fiber_shadow), clamp01(p.fiber_shadow_floor));
    const float shadow =
        traced_ ? fiber_shadow : std::max(clamp01(point.ply_shadow), clamp01(p.ply_shadow_floor)) * fiber_shadow;
    int colors = static_cast<int>(p.ply_color_count >= 1 ? std::min(p.ply_color_count, float(kMaxPlyColors)) : 1);
    const int ply = point.ply_index >= 0 ? point.ply_index % colors : 0;
    const Vec3 tint = clamp01(p.ply_colors[ply]) * clamp01(point.yarn_color);
    k_body_r_ = clamp01(p.body_reflection_albedo * tint) * (body * shadow);
    k_body_t_ = clamp01(p.body_transmission_albedo * tint) * (body * shadow);

    mean_spec_r_ = average(k_spec_r_);
    mean_spec_t_ = average(k_spec_t_);
    mean_body_r_ = average(k_body_r_);
    mean_body_t_ = average(k_body_t_);
    r0_ = clamp01(p.body_reflection_share);
    r_fresnel_ = clamp01(p.body_reflection_fresnel);
    ls_weight_ = clamp01(p.lommel_seeliger_weight);

    const float plies = traced_ ? 1.0f : static_cast<float>(std::max(1, point.plies_crossed));
    sigma_spec_ = std::max(0.0f, p.sigma_t_specular);
    sigma_body_ = std::max(0.0f, p.sigma_t_body);
    if (!(sigma_spec_ < 1e30f)) sigma_spec_ = 1e30f;  // inf or NaN: opaque
    if (!(sigma_body_ < 1e30f)) sigma_body_ = 1e30f;
    extinction_spec_ = std::min(sigma_spec_ * plies, 1e30f);
    extinction_body_ = std::min(sigma_body_ * plies, 1e30f);
    if (traced_) {
        // What one more ply passes on: its four lobes as a whole, Fresnel averaged over the
        // hemisphere (Kulla and Conty's fit, within 1e-2 for eta 1-3), the ply's mean G_f.
        const float fresnel_avg = (eta_ - 1.0f) / (4.08567f + 1.00071f * eta_);
        const float ply_shadow = std::max(clamp01(point.mean_fiber_shadow), clamp01(p.fiber_shadow_floor));
        const Vec3 body_x = clamp01(p.body_reflection_albedo * tint) * (body * ply_shadow);
        const Vec3 body_y = clamp01(p.body_transmission_albedo * tint) * (body * ply_shadow);
        pass_on_.specular_transmission = k_spec_t_ * (1.0f - fresnel_avg);
        pass_on_.body_transmission = body_y * (1.0f - r0_);
        pass_on_.reflection = k_spec_r_ * fresnel_avg + body_x * r0_;
        pass_on_.sigma_specular = sigma_spec_;
        pass_on_.sigma_body = sigma_body_;
    }
}

Vec3 PlyPassOn::product(const PlyCrossings& plies) const { return product(plies.others, plies.other); }

Vec3 PlyPassOn::scattered(const PlyCrossings& plies) const {
    // On the straight line to the light a crossed ply's reflection leaves on the light's side,
    // away from the hit: only its transmission gets through. Beside the line (the spread
    // directions) its reflection can reach the hit too, so those carry the whole A_k.
    Vec3 sum = plies.others > 0 ? product(plies.others, plies.other, false) : Vec3(0.0f);
    if (!plies.spread_done) return sum;
    for (int m = 0; m < kSpreadDirections; ++m)
        if (plies.spread_others[m] > 0) sum += product(plies.spread_others[m], plies.spread[m]);
    return sum * (1.0f / (1 + kSpreadDirections));
}

Vec3 PlyPassOn::product(int count, const float* lengths, bool with_reflection) const {
    Vec3 t(1.0f);
    const int n = std::clamp(count, 0, kMaxCrossedPlies);
    const Vec3 reflected = with_reflection ? reflection : Vec3(0.0f);
    for (int k = 0; k < n; ++k) {
        const float L = std::max(0.0f, lengths[k]);
        const float spec = sigma_specular * L < 100.0f ? std::exp(-sigma_specular * L) : 0.0f;
        const float body = sigma_body * L < 100.0f ? std::exp(-sigma_body * L) : 0.0f;
        t = t * (specular_transmission * spec + body_transmission * body + reflected);
    }
    return t;
}

float Bysdf::body_reflection_share(float cos_o) const {
    if (r_fresnel_ == 0) return r0_;
    return (1.0f - r_fresnel_) * r0_ + r_fresnel_ * fresnel_dielectric(cos_o, eta_);
}

float Bysdf::transmittance(int body, float chord) const {
    const float extinction = body ? extinction_body_ : extinction_spec_;
    if (!(chord > 0) || extinction == 0) return 1.0f;  // also a NaN chord
    const float optical_depth = extinction * chord;
    return optical_depth < 100.0f ? std::exp(-optical_depth) : 0.0f;  // inf chord: opaque
}

void Bysdf::lobe_probabilities(Vec3 wo, float prob[4]) const {
    const float cos_o = std::fabs(wo.z);
    // Energy each lobe would take; the macro-surface Fresnel splits the specular energy.
    const float fresnel = fresnel_dielectric(cos_o, eta_);
    const float r = body_reflection_share(cos_o);
    prob[kSpecularReflection] = mean_spec_r_ * fresnel;
    prob[kSpecularTransmission] = mean_spec_t_ * (1.0f - fresnel);
    prob[kBodyReflection] = mean_body_r_ * r;
    prob[kBodyTransmission] = mean_body_t_ * (1.0f - r);
    const float total = prob[0] + prob[1] + prob[2] + prob[3];
    const float scale = total > 0 ? 1.0f / total : 0.0f;
    for (int i = 0; i < 4; ++i) prob[i] *= scale;
}

void Bysdf::lobe_albedos(Vec3 wo, Vec3 albedo[4]) const {
    const float cos_o = std::fabs(wo.z);
    const float fresnel = fresnel_dielectric(cos_o, eta_);
    const float r = body_reflection_share(cos_o);
    albedo[kSpecularReflection] = k_spec_r_ * fresnel;
    albedo[kSpecularTransmission] = k_spec_t_ * (1.0f - fresnel);
    albedo[kBodyReflection] = k_body_r_ * r;
    albedo[kBodyTransmission] = k_body_t_ * (1.0f - r);
}

float Bysdf::lobe_roughness(int lobe) const {
    if (lobe == kSpecularReflection) return std::sqrt(reflection_ggx_.alpha_x * reflection_ggx_.alpha_y);
    if (lobe == kSpecularTransmission) return transmission_ggx_.alpha_x;
    return 1.0f;
}

template <bool kWithPdf>
BsdfEvalPdf Bysdf::evaluate(Vec3 wo, Vec3 wi, float chord, const PlyCrossings* plies) const {
    ++evaluations;
    BsdfEvalPdf out;
    // Traced: the hit ply's own path attenuates the transmission lobes, the other plies all.
    const bool crossing = traced_ && plies;
    if (crossing) chord = plies->own;
    PlyCrossings spread;  // the spread crossing marches its extra directions only now
    if (crossing && spread_ && !plies->spread_done && plies->yarn) {
        spread = *plies;
        add_spread(spread);
        plies = &spread;
    }
    if (!(std::fabs(wo.z) > kMinCos && std::fabs(wi.z) > kMinCos)) return out;  // also NaN
    if (wo.z < 0) {  // two-sided: mirror so the viewer is on +z
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    float prob[4] = {0, 0, 0, 0};
    if (kWithPdf) lobe_probabilities(wo, prob);
    const float cos_o = wo.z;
    // One Fresnel split for both specular lobes (see lobe_probabilities): their roughnesses
    // differ, so per-microfacet Fresnel factors would not sum to one and the pair could
    // return more than it receives at grazing angles (measured: up to 1.10).
    const float fresnel = fresnel_dielectric(cos_o, eta_);

    if (wi.z > 0) {
        const float cos_i = wi.z;
        const Vec3 h = normalize(wo + wi);  // both above: never the zero vector
        const float cos_oh = dot(wo, h);
        const float d = reflection_ggx_.d(h);
        out.f = k_spec_r_ * (fresnel * d * reflection_ggx_.g2(wo, wi) / (4 * cos_o * cos_i));

        const float r = body_reflection_share(cos_o);
        const float shape = (ls_weight_ * lommel_seeliger(cos_o, cos_i) + kInvPi) /
                            (1.0f + ls_weight_ * lommel_seeliger_albedo(cos_o));
        out.f += k_body_r_ * (r * shape);

        if (kWithPdf && prob[kSpecularReflection] > 0 && cos_oh > 0)
            out.pdf += prob[kSpecularReflection] * reflection_ggx_.visible_normal_pdf(wo, h) / (4 * cos_oh);
        out.pdf += prob[kBodyReflection] * cos_i * kInvPi;
        if (crossing && spread_) {  // what met another ply arrives diffuse: the lobes' albedo / pi
            if (plies->others > 0) out.f = Vec3(0.0f);
            out.f += (k_spec_r_ * fresnel + k_body_r_ * r) * kInvPi * pass_on_.scattered(*plies);
        } else if (crossing && plies->others > 0) {
            out.f = out.f * other_plies_transmission(*plies);
        }
        return out;
    }

    const float cos_i = -wi.z;
    Vec3 h;
    float cos_oh, cos_ih;
    if (transmission_half_vector(wo, wi, eta_, h, cos_oh, cos_ih)) {
        const float denom = cos_oh + eta_ * cos_ih;
        const float denom2 = denom * denom;
        if (denom2 > 0) {
            // dwh/dwi of the refraction; eta^2 cancels Walter's radiance compression (see docs).
            const float jacobian = eta_ * eta_ * -cos_ih / denom2;
            const float d = transmission_ggx_.d(h);
            out.f = k_spec_t_ * ((1.0f - fresnel) * d * transmission_ggx_.g2(wo, wi) * cos_oh * jacobian /
                                 (cos_o * cos_i) * transmittance(0, chord));
            if (kWithPdf && prob[kSpecularTransmission] > 0)
                out.pdf += prob[kSpecularTransmission] * transmission_ggx_.visible_normal_pdf(wo, h) * jacobian;
        }
    }
    const float r = body_reflection_share(cos_o);
    out.f += k_body_t_ * ((1.0f - r) * kInvPi * transmittance(1, chord));
    out.pdf += prob[kBodyTransmission] * cos_i * kInvPi;
    if (crossing && spread_) {
        if (plies->others > 0) out.f = Vec3(0.0f);
        out.f += (k_spec_t_ * ((1.0f - fresnel) * transmittance(0, chord)) +
                  k_body_t_ * ((1.0f - r) * transmittance(1, chord))) *
                 kInvPi * pass_on_.scattered(*plies);
    } else if (crossing && plies->others > 0) {
        out.f = out.f * other_plies_transmission(*plies);
    }
    return out;
}

template BsdfEvalPdf Bysdf::evaluate<false>(Vec3, Vec3, float, const PlyCrossings*) const;
template BsdfEvalPdf Bysdf::evaluate<true>(Vec3, Vec3, float, const PlyCrossings*) const;

std::optional<BsdfSample> Bysdf::sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* exit) const {
    if (!(std::fabs(wo.z) > kMinCos)) return std::nullopt;
    const bool flipped = wo.z < 0;
    if (flipped) wo.z = -wo.z;
    float prob[4];
    lobe_probabilities(wo, prob);

    // Pick the lobe whose cumulative probability first exceeds u_lobe.
    int lobe = -1;
    float cumulative = 0;
    for (int i = 0; i < 4; ++i) {
        cumulative += prob[i];
        if (prob[i] > 0 && u_lobe < cumulative) {
            lobe = i;
            break;
        }
    }
    if (lobe < 0) {  // rounding left u_lobe above the last sum: take the last non-empty lobe
        for (int i = 3; i >= 0 && lobe < 0; --i)
            if (prob[i] > 0) lobe = i;
        if (lobe < 0) return std::nullopt;
    }

    BsdfSample s;
    s.lobe = lobe;
    switch (lobe) {
        case kSpecularReflection:
            s.wi = reflect(wo, reflection_ggx_.sample_visible_normal(wo, u));
            s.flags = kBsdfReflection | kBsdfSpecular;
            break;
        case kSpecularTransmission:
            if (!refract(wo, transmission_ggx_.sample_visible_normal(wo, u), eta_, s.wi)) return std::nullopt;
            s.flags = kBsdfTransmission | kBsdfSpecular;
            break;
        case kBodyReflection:
            s.wi = sample_cosine_hemisphere(u);
            s.flags = kBsdfReflection | kBsdfBody;
            break;
        default:
            s.wi = sample_cosine_hemisphere(u);
            s.wi.z = -s.wi.z;
            s.flags = kBsdfTransmission | kBsdfBody;
            break;
    }
    // A rough lobe may send wi to the wrong side; that energy is lost, as in pbrt.
    const bool wants_reflection = (s.flags & kBsdfReflection) != 0;
    if (wants_reflection ? !(s.wi.z > kMinCos) : !(s.wi.z < -kMinCos)) return std::nullopt;

    // Value and density of the whole mixture, so that weight = f cos / pdf is exact for MIS;
    // f attenuated along the exit when the caller gives it (the density does not depend on it).
    ScatterExit along;
    if (exit) along = exit->toward(flipped ? Vec3(s.wi.x, s.wi.y, -s.wi.z) : s.wi);
    const BsdfEvalPdf ep = evaluate<true>(wo, s.wi, along.chord, along.plies);
    if (!(ep.pdf > 0)) return std::nullopt;
    s.f = ep.f;
    s.pdf = ep.pdf;
    if (flipped) s.wi.z = -s.wi.z;
    return s;
}

}  // namespace purl
