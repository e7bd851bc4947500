// BYSDF: the four-lobe yarn scattering model of Khattar et al. 2024, "A Multi-scale Yarn
// Appearance Model with Fiber Details", section 4.1, in the local frame of a fiber hit:
// normal +z, fiber tangent +x; wo (toward the viewer) and wi (toward the light) point away.
//
//   f_x^S  (1-B) k_x^S F G2 D(h) / (4 |cos_o cos_i|)                 rough reflection, alpha (along, across)
//   f_y^S  (1-B) k_y^S tau_S (1-F) G2 D(h) eta^2 |wi.h| |wo.h| / (|cos_o cos_i| (wo.h + eta wi.h)^2)
//                                                                      Walter 2007 transmission, alpha_t
//   f_x^B  r B G k_x^B (w LS(wo,wi) + 1/pi) / (1 + w A_LS(cos_o))      back-scattered body
//   f_y^B  (1-r) B G k_y^B tau_B / pi                                  forward-scattered body
//
// with G = max(G_p, floor_p) max(G_f, floor_f), tau = exp(-sigma_t chord)^N_i, chord the
// distance |x - y| through the yarn divided by the yarn radius, A_LS the LS albedo (so the
// body lobes reflect and transmit exactly B G k), r = (1-t) r0 + t F, and F = F(cos_o, eta)
// the dielectric Fresnel reflectance at the viewing angle (one split for both specular lobes).
// That is the paper's ply crossing (ply_crossing 0). With ply_crossing 1 (traced) the renderer
// passes the plies the outgoing ray crosses (yarn/ply_crossings.h): tau runs over the hit ply's
// own path only, G drops G_p, and every lobe is multiplied by what each other ply crossed
// passes on, A_k = (1-B) k_y^S (1-F_avg) e^(-sigma_tS L_k) + (1-r0) B G_k k_y^B e^(-sigma_tB L_k)
// + (1-B) k_x^S F_avg + r0 B G_k k_x^B (its transmission plus its reflection: exact when the
// light around that ply is the same on both sides), G_k = max(mean G_f, floor_f).
// ply_crossing 2 (spread) keeps the lobes as they are for light that meets no other ply, and
// for light another ply has scattered uses the lobes' albedos on wi's side over pi (that light
// arrives diffuse), times what the other plies pass on, averaged over the ray (their
// transmission only: a ply's reflection there leaves toward the light) and kSpreadDirections
// directions around it (their whole A_k: a ply's glow reaches the hit from beside the line).
// The surface is two-sided: when wo.z < 0 both directions are mirrored through z = 0.
// Deviations from the paper and the renderer contract are in docs/bysdf.md.
#pragma once
#include <algorithm>
#include <cstdint>
#include <optional>

#include "bsdf/bsdf_sample.h"
#include "bsdf/bysdf_params.h"
#include "bsdf/ggx.h"
#include "bsdf/scatter_exit.h"
#include "yarn/ply_crossings.h"

namespace purl {

// What the implicit yarn geometry knows about one hit; plain inputs, no geometry types.
struct BysdfShadingPoint {
    float ply_shadow = 1.0f;    // G_p in [0, 1] (ply-shadowing map)
    float fiber_shadow = 1.0f;  // G_f in [0, 1] (fiber-shadowing map)
    int plies_crossed = 1;      // N_i >= 1, plies crossed along the ray's cross-section
    int ply_index = 0;          // which ply was hit, selects the ply colour
    Vec3 yarn_color{1.0f};      // per-yarn colour override; multiplies the body albedos
    float mean_fiber_shadow = 1.0f;  // G_f over a whole ply (FiberMaps): the other plies' shadowing
};

// Traced ply crossing: what each further ply crossed passes on, A_k, per channel.
struct PlyPassOn {
    Vec3 specular_transmission, body_transmission;  // before extinction over the path L_k
    Vec3 reflection;                                // both reflection lobes
    float sigma_specular = 0, sigma_body = 0;       // per yarn radius
    Vec3 product(const PlyCrossings& plies) const;  // over the other plies crossed (1 when none)
    // `with_reflection` false: each ply passes on its transmission only.
    Vec3 product(int count, const float* lengths, bool with_reflection = true) const;
    // Light the other plies scatter toward the hit: the product over the plies crossed, averaged
    // over the ray (transmission only) and its spread directions (whole A_k), 0 where a
    // direction meets no other ply.
    Vec3 scattered(const PlyCrossings& plies) const;
};

// BYSDF evaluations (eval, pdf, eval_pdf, sample: one each) made on the calling thread so far:
// the renderer's statistics count them (RenderStats::bysdf_evaluations).
uint64_t bysdf_evaluations_on_this_thread();

class Bysdf {
public:
    enum Lobe { kSpecularReflection = 0, kSpecularTransmission = 1, kBodyReflection = 2, kBodyTransmission = 3 };

    Bysdf(const BysdfParams& params, const BysdfShadingPoint& point);

    // Model value without the cosine, 1/sr. `exit.chord` (|x - y| / yarn radius) only matters
    // when wi is on the other side of the yarn; 0 means "no attenuation known yet".
    // `exit.plies`: what the ray toward wi crosses (traced ply crossing); null: nothing known,
    // only the hit ply's chord attenuates. The density does not depend on the exit.
    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& exit = {}) const {
        return evaluate<false>(wo, wi, exit.chord, exit.plies).f;
    }
    // Solid-angle density of `sample`, 1/sr.
    float pdf(Vec3 wo, Vec3 wi) const { return evaluate<true>(wo, wi, 0.0f, nullptr).pdf; }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& exit = {}) const {
        return evaluate<true>(wo, wi, exit.chord, exit.plies);
    }
    bool traces_plies() const { return traced_; }  // ply_crossing 1, 2: wants PlyCrossings

    // Chooses a lobe with u_lobe in [0, 1), then a direction with u in [0, 1)^2. With `exit`,
    // the sampled direction's exit is asked before the one evaluation, so f comes out
    // attenuated along it; without, f is unattenuated (chord 0). See docs/bysdf.md.
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* exit = nullptr) const;

    // Probabilities of choosing each Lobe for this wo (they sum to 1, or all are 0).
    void lobe_probabilities(Vec3 wo, float prob[4]) const;
    // Per channel, the share of white light each Lobe scatters for this wo (the energies the
    // lobe probabilities average, before masking losses and extinction): the denoiser's albedo.
    void lobe_albedos(Vec3 wo, Vec3 albedo[4]) const;
    // GGX alpha of a specular Lobe (the geometric mean of the two for the reflection); 1 for
    // the body lobes, which are diffuse.
    float lobe_roughness(int lobe) const;
    // exp(-sigma_t chord)^N_i for the specular (0) or body (1) transmission (paper), or
    // exp(-sigma_t chord) (traced: `chord` is then the path inside the hit ply).
    float transmittance(int body, float chord) const;
    // Traced: the product over the other plies crossed of what they pass on, A_k (1 when none).
    Vec3 other_plies_transmission(const PlyCrossings& plies) const { return pass_on_.product(plies); }
    const PlyPassOn& pass_on() const { return pass_on_; }
    // Raises the GGX alpha of both specular lobes to at least `min_alpha` (path regularisation,
    // render/path_regularization.h); the lobe energies stay as they are.
    void roughen(float min_alpha) {
        reflection_ggx_.alpha_x = std::max(reflection_ggx_.alpha_x, min_alpha);
        reflection_ggx_.alpha_y = std::max(reflection_ggx_.alpha_y, min_alpha);
        transmission_ggx_.alpha_x = std::max(transmission_ggx_.alpha_x, min_alpha);
        transmission_ggx_.alpha_y = std::max(transmission_ggx_.alpha_y, min_alpha);
    }

private:
    template <bool kWithPdf>
    BsdfEvalPdf evaluate(Vec3 wo, Vec3 wi, float chord, const PlyCrossings* plies) const;
    float body_reflection_share(float cos_o) const;

    Ggx reflection_ggx_, transmission_ggx_;
    float eta_ = 1.5f;
    Vec3 k_spec_r_, k_spec_t_;  // (1 - B) k^S
    Vec3 k_body_r_, k_body_t_;  // B G k^B x ply colour x yarn colour
    float mean_spec_r_ = 0, mean_spec_t_ = 0, mean_body_r_ = 0, mean_body_t_ = 0;
    float r0_ = 0.5f, r_fresnel_ = 0.0f;
    float ls_weight_ = 1.0f;
    float extinction_spec_ = 0, extinction_body_ = 0;  // sigma_t N_i (paper) or sigma_t (traced), per unit chord
    bool traced_ = false;
    bool spread_ = false;  // ply_crossing 2: light other plies scattered arrives diffuse, from around the ray
    float sigma_spec_ = 0, sigma_body_ = 0;  // sigma_t per yarn radius
    PlyPassOn pass_on_;  // traced: A_k's parts
};

}  // namespace purl
