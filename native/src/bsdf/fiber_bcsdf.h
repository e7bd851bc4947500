// The fiber scattering function of Khungurn et al. 2015, "Matching Real Fabrics with
// Micro-Appearance Models" (a far-field model of one fiber, after Marschner et al. 2003), for
// the fiber-based reference. Local frame: fiber tangent +x; theta is the longitudinal angle
// (asin of the x component, from the normal plane), phi the azimuth around the fiber.
// wo points to the viewer, wi to the light.
//
//   S(wo, wi) = F M_R(theta_i | theta_o) / (2 pi)                          R: surface reflection
//             + (1 - F) A_TT M_TT(theta_i | theta_o) N_TT(phi_i - phi_o - pi)  TT: through the fiber
//
//   F      = A_R + (1 - A_R) (1 - cos theta_o)^5       Schlick, per channel, at the viewer
//   M(.|theta_o) = N(theta_i; -theta_o, beta^2) / G, G = integral over [-pi/2, pi/2] of
//            N(theta; -theta_o, beta^2) cos^2 theta: "cos^2-normalised", so the R lobe
//            scatters exactly F and the TT lobe exactly (1 - F) A_TT
//   N_TT(phi) = N(phi; 0, gamma^2) + (1 - mass in [-pi, pi]) / (2 pi)   on [-pi, pi]
//
// Light leaves as L_o = integral of S L_i cos theta_i dw_i. The renderer multiplies by |wi.z|
// (the frame normal), so eval returns S cos theta_i / |wi.z|: any frame with x along the fiber
// gives the same light. Directions within 1e-6 of the frame's tangent plane get value 0.
// Sampling: lobe by energy, theta_i from the truncated normal N(-theta_o, beta^2) on
// [-pi/2, pi/2], phi uniform (R) or exactly from N_TT (TT); pdf is the whole mixture.
//
// Per-material data (the G tables) live in FiberBcsdf, built once and shared by all threads;
// shading points hold a FiberBcsdfRef.
#pragma once
#include <optional>
#include <vector>

#include "bsdf/bsdf_sample.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "bsdf/scatter_exit.h"

namespace purl {

// M(theta_i | theta_o) for one width, with its normalisation tabulated over the mean.
class FiberLongitudinalLobe {
public:
    explicit FiberLongitudinalLobe(float width_rad);
    // Density per radian of theta_i, normalised so that its integral times cos^2 is 1.
    float eval(float theta_i, float theta_o) const;
    // theta_i in [-pi/2, pi/2] from the truncated normal around -theta_o, for u in [0, 1).
    float sample(float theta_o, float u) const;
    // Density per radian of `sample`.
    float sample_pdf(float theta_i, float theta_o) const;
    // G(mean): the cos^2-weighted mass of N(mean, width^2) on [-pi/2, pi/2].
    double normalisation(double mean) const;
    float width() const { return static_cast<float>(sigma_); }

private:
    double sigma_;
    double step_;              // table spacing in |mean|, rad
    std::vector<float> norm_;  // G at |mean| = k step_, k = 0 .. n
};

class FiberBcsdf {
public:
    enum Lobe { kReflection = 0, kTransmission = 1 };

    explicit FiberBcsdf(const FiberBcsdfParams& params);

    // Model value for the renderer's |wi.z| convention, 1/sr.
    Vec3 eval(Vec3 wo, Vec3 wi) const;
    // S(wo, wi) cos theta_i: the value against the fiber's own cosine, frame-independent.
    Vec3 scattering(Vec3 wo, Vec3 wi) const;
    // Solid-angle density of `sample`, 1/sr.
    float pdf(Vec3 wo, Vec3 wi) const;
    // u_lobe picks R or TT (and, for TT, the Gaussian or uniform part of N_TT); u the direction.
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u) const;
    // Probabilities of choosing R and TT for this wo (sum 1, or both 0).
    void lobe_probabilities(Vec3 wo, float prob[2]) const;

    const FiberBcsdfParams& params() const { return params_; }

private:
    Vec3 fresnel(float cos_theta_o) const;
    void lobe_probabilities(float cos_theta_o, float prob[2]) const;
    float azimuthal_tt(float phi_d) const;  // N_TT, per radian
    float sample_azimuth_tt(float u_choice, float u) const;

    FiberBcsdfParams params_;
    Vec3 reflection_color_, transmission_color_;  // clamped to [0, 1]
    FiberLongitudinalLobe r_, tt_;
    double gamma_;         // N_TT width, rad
    double gamma_mass_;    // mass of N(0, gamma^2) inside [-pi, pi]
};

// What a shading point holds: a pointer to the per-material model. A fiber's exit (through its
// own cylinder) does not attenuate: the fiber reference meets the next fiber by tracing.
struct FiberBcsdfRef {
    const FiberBcsdf* model = nullptr;
    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return model->eval(wo, wi); }
    float pdf(Vec3 wo, Vec3 wi) const { return model->pdf(wo, wi); }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const {
        return {model->eval(wo, wi), model->pdf(wo, wi)};
    }
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* = nullptr) const {
        return model->sample(wo, u_lobe, u);
    }
};

}  // namespace purl
