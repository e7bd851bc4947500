// Multi-scale BYSDF (Khattar et al. 2024, sections 4.2 and 5.2): the yarn's BYSDF averaged
// over the pixel footprint [h1, h2] across the yarn, so a distant yarn needs no supersampling.
//
//   f_multi(wo, wi) = 1/C^ integral_{h1}^{h2} W(h) f_near(wo, wi, h) dh          (eq. 8)
//   f_far           = f_multi over [-1, 1]                                         (eq. 7)
//
// W(h) = 1 (box): h is uniform in projected width, so a box pixel sees every h of its
// footprint equally; C = integral_{-1}^{1} W = 2 and C^ = h2 - h1. The integral is taken by K
// stratified samples of h (one per `sample_spacing` fiber diameters covered, 1..max_h_samples).
// The stratum holding h0 uses the camera ray itself (h0 is uniform over the pixel); the others
// are jittered by one per-hit random number, and for each a virtual ray parallel to the camera
// ray, offset across the yarn, enters the tube and goes through the implicit ply query on the
// yarn straightened at the camera ray's cross-section (PlyQuery::around: no curve evaluation)
// and the fiber maps. A ray between the plies passes straight through (pass_fraction).
//
// Aggregation::Mixture (default) keeps each h_k's own frame, shading values and position:
//   f~(wo, wi) |cos_ref| = sum_k w_k f_k(wo, wi) |cos_k|,   pdf = sum_k w_k pdf_k,
// where cos_k is taken against h_k's fiber normal and cos_ref against the reference frame
// (aggregated normal and tangent, eqs. 9-10): eval returns f~, so the renderer's usual
// f |cos_ref| / pdf is exact. Transmission through the yarn is attenuated per h_k along its
// own chord (local straight tube). Aggregation::Aggregate is the paper's shortcut: one BYSDF
// in the aggregated frame with G_multi (eq. 11), the mean G_p, N_i and ply colour.
// Both use beta_multi = beta + (h2 - h1) / C_beta on the three specular roughnesses.
//
// Rays leave from one point: the camera ray's own ply hit, else the hit nearest h0
// (docs/multiscale.md). The CurveFrames and maps must outlive the model.
//
// In the renderer, far hits shade the tabulated far field (far_field.h); this class in mode
// Far is what the table is built from and tested against.
#pragma once
#include <tbb/collaborative_call_once.h>

#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bsdf/bysdf.h"
#include "math/frame.h"
#include "render/far_field.h"
#include "render/footprint.h"
#include "scene/multiscale_settings.h"
#include "yarn/fiber_maps.h"
#include "yarn/implicit_plies.h"
#include "yarn/ply_crossings.h"
#include "yarn/yarn_description.h"
#include "yarn/yarn_tube.h"

namespace purl {

// Width in h (yarn radii) of one fiber: 2 fiber_radius ply_radius; the smallest feature.
float fiber_feature_width(const YarnDescription& d);
// K for a covered range `width` (h units): ceil(width / (spacing x fiber)), clamped to 1..max.
int h_sample_count(float width, const YarnDescription& d, const MultiscaleSettings& s);

// Resolves Auto per hit, and warns once (per selector) when Far is forced on a yarn that is
// wider than a pixel (the paper's Fig. 8 caveat). Thread-safe; one per render.
class MultiscaleSelector {
public:
    using WarningSink = std::function<void(const std::string&)>;
    // An empty sink prints to stderr. `yarn_sets`: how many far-field tables to keep at hand.
    explicit MultiscaleSelector(const MultiscaleSettings& settings, WarningSink sink = {}, size_t yarn_sets = 0);
    // Near, Multi or Far. Auto: near without a valid footprint, below near_limit fibers or on
    // yarns at least near_pixels wide, far when the footprint reaches both silhouettes or one
    // pixel spans far_limit yarn diameters, multi otherwise.
    MultiscaleMode choose(const AzimuthalFootprint& f, const YarnDescription& d) const;
    bool warned() const { return warned_.load(std::memory_order_relaxed); }
    const MultiscaleSettings& settings() const { return settings_; }
    // The tabulated far field of yarn set `set` (its description and material), looked up in
    // the process cache (far_field_table) on first use in this render. Null for set >=
    // yarn_sets: the caller shades far hits with the sampled far field (MultiscaleBysdf) then.
    const FarFieldTable* far_table(size_t set, const YarnDescription& d, const BysdfParams& material) const;

private:
    struct TableSlot {
        tbb::collaborative_once_flag once;  // threads waiting for the build help with it
        std::shared_ptr<const FarFieldTable> table;
    };
    MultiscaleSettings settings_;
    WarningSink sink_;
    mutable std::atomic<bool> warned_{false};
    std::unique_ptr<TableSlot[]> tables_;
    size_t table_count_ = 0;
};

// The yarn a hit belongs to: what SurfaceShader keeps per yarn set and curve.
struct MultiscaleYarn {
    const CurveFrames* frames = nullptr;
    const YarnDescription* description = nullptr;
    const FiberMaps* maps = nullptr;
    const BysdfParams* params = nullptr;
    uint32_t curve_key = 0;       // as passed to trace_yarn_hit
    Vec3 yarn_color{1.0f};        // BysdfShadingPoint::yarn_color
    PlyTraceOptions trace{};
    // The far-field table's build: `params` holds lobe markers in place of the albedos, and the
    // other plies' A_k (traced ply crossing) come from these colours, kept apart
    // (component_integrand's `crossed`). Null: params' own colours.
    const BysdfParams* crossing_colors = nullptr;
};

// One camera-ray hit on the yarn tube.
struct MultiscaleQuery {
    YarnTubeHit tube;               // the ray and its tube entry
    CentrelineProjection axis;      // project_to_centreline(frames, tube.point, tube.segment, tube.t)
    AzimuthalFootprint footprint;   // yarn_footprint(ray, tube.point, axis.point, footprint_scale)
    MultiscaleMode mode = MultiscaleMode::Multi;  // Near, Multi or Far (resolve Auto first)
    float u_strata = 0.5f;          // per-hit random number in [0, 1): jitters the h samples
};

class MultiscaleBysdf {
public:
    struct Component {
        std::optional<Bysdf> bsdf;  // the BYSDF at h_k, with beta_multi
        Frame frame;                // its fiber frame, in the reference frame's local coordinates
        Vec3 offset;                // its ply point minus the axis point, yarn radii, local coordinates
        float h = 0;                // its azimuthal offset
        float weight = 0;           // w_k, summing to 1 over the components
        int ply = 0;                // ply index of its hit (selects the ply colour)
        PlySection section;         // traced ply crossing: its hit in local coordinates, yarn radii
        PlyPassOn crossing_colors;  // with MultiscaleYarn::crossing_colors: what the plies crossed pass on
    };

    MultiscaleBysdf(const MultiscaleYarn& yarn, const MultiscaleSettings& settings, const MultiscaleQuery& q);

    // Share of the footprint (h samples) that passes between the plies: continue the camera
    // ray straight through with this probability (pass_distance further than the tube entry).
    float pass_fraction() const { return pass_fraction_; }
    float pass_distance() const;  // m; computed on demand (a tube exit search)
    bool empty() const { return count_ == 0; }              // every h passes: pass_fraction 1

    // Reference frame: +z = aggregated normal n_multi (eq. 9), +x = aggregated tangent (eq. 10).
    const Frame& frame() const { return frame_; }
    Vec3 position() const { return position_; }  // m, the camera ray's ply hit (else the hit nearest h0): rays leave here
    uint32_t segment() const { return segment_; }  // centre-line parameter of position()
    // The ply hit position() lies on (-1 when empty()): index, u_ply (rad), v_ply (m).
    int ply() const { return ply_; }
    float u_ply() const { return u_ply_; }
    float v_ply() const { return v_ply_; }
    float t() const { return t_; }

    // Local (reference-frame) directions, pointing away. f~ (1/sr) such that f~ |wi.z| is the
    // footprint-averaged integrand; attenuation through the yarn is included, each h_k along its
    // own chord, so the shading point's exit is not needed (render/scattering.h).
    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return evaluate(wo, wi).f; }
    float pdf(Vec3 wo, Vec3 wi) const { return evaluate(wo, wi).pdf; }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return evaluate(wo, wi); }
    // Picks h_k by w_k with u_lobe (rescaled, reused for the lobe), samples its BYSDF. f and
    // pdf are the whole mixture's, attenuated: use them as they are.
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery* = nullptr) const;

    // Diagnostics and tests.
    MultiscaleMode mode() const { return mode_; }
    int samples() const { return samples_; }        // K, h samples traced
    int components() const { return count_; }       // Mixture: hits among them; Aggregate: 1
    const Component& component(int k) const { return components_[k]; }
    // Component k's share of the integrand, w_k f_k |cos_k| (attenuated); with `pdf`, adds w_k pdf_k there.
    // With `crossed` (traced crossing only), the other plies' A_k product is left out of the
    // result and returned there, from MultiscaleYarn::crossing_colors when given.
    Vec3 component_integrand(int k, Vec3 wo, Vec3 wi, float* pdf = nullptr, Vec3* crossed = nullptr) const;
    float h1() const { return h1_; }
    float h2() const { return h2_; }
    float roughness_increase() const { return roughness_increase_; }  // (h2 - h1) / C_beta
    float fiber_shadow() const { return g_multi_; }  // G_multi (eq. 11) over the hits

private:
    BsdfEvalPdf evaluate(Vec3 wo, Vec3 wi) const;
    // Component c's BYSDF at its own directions, attenuated along wi (reference frame).
    BsdfEvalPdf component_eval(const Component& c, Vec3 wo_k, Vec3 wi_k, Vec3 wi, Vec3* crossed = nullptr) const;

    std::array<Component, kMaxHSamples> components_;
    int count_ = 0, samples_ = 0;
    bool same_frame_ = false;  // one component in the reference frame: no cosine ratio needed
    Frame frame_;
    Vec3 position_, axis_tangent_;  // axis_tangent_: the yarn tangent in local coordinates
    uint32_t segment_ = 0;
    float t_ = 0;
    int ply_ = -1;
    float u_ply_ = 0, v_ply_ = 0;
    float pass_fraction_ = 0;
    const CurveFrames* frames_ = nullptr;  // for pass_distance: the tube entry and its parameter
    YarnTubeHit entry_;
    uint32_t axis_segment_ = 0;
    float axis_t_ = 0;
    const YarnDescription* crossing_ = nullptr;  // traced ply crossing: the plies to cross
    float h1_ = 0, h2_ = 0, roughness_increase_ = 0, g_multi_ = 1;
    MultiscaleMode mode_ = MultiscaleMode::Near;
};

}  // namespace purl
