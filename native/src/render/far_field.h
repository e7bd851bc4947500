// Tabulated far field (Khattar et al. 2024, eq. 7, precomputed as the paper does): the BYSDF
// integrated over the whole yarn width, h in [-1, 1], and averaged over the ply phase along the
// yarn (a sub-pixel footprint also covers a length of yarn), for one yarn description and
// material. Averaged over the phase the yarn is a cylinder, so the integrand depends only on
// the directions in the yarn frame: theta_o, theta_i (from the normal plane) and phi_i - phi_o.
//
// The table is built once per (description, material, C_beta) from the sampled far field
// (MultiscaleBysdf in mode Far, so the traced h samples, chords, ply crossing and roughening are
// the same model) on a straight yarn, and cached per process. The lobe at the hit is linear in
// its colours, so it stores per lobe group: specular reflection and transmission (x k^S), body
// reflection and transmission per ply-colour class (x k^B x ply colour), a curve's own colours
// multiplying at lookup. Light that crosses other plies on its way out (traced crossing) is
// multiplied by their A_k, a product of the material's albedos: that factor is tabulated per
// channel from the material's colours (so the groups are RGB, and a curve recoloured by
// curve_colors keeps the material's A_k). Also per theta_o: the pass-through fraction and, for
// sampling, piecewise-constant distributions (specular, body) over the incoming cells.
//
// Approximations (docs/multiscale.md): the yarn is straight (curvature ignored), the phase is
// averaged, and f is constant over each cell of wi (interpolated linearly in sin theta_o).
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "bsdf/bsdf_sample.h"
#include "bsdf/bysdf.h"
#include "math/sampling.h"
#include "scene/multiscale_settings.h"
#include "yarn/yarn_description.h"

namespace purl {

class FarFieldTable {
public:
    static constexpr int kThetaO = 32;  // nodes in sin theta_o
    static constexpr int kThetaI = 24;  // cells in sin theta_i (equal solid angle)
    static constexpr int kPhi = 36;     // cells in phi_i - phi_o
    static constexpr int kCells = kThetaI * kPhi;

    // `queries`: sampled far-field models per theta_o node (each traces up to 16 h samples);
    // every cell takes one jittered direction from every `cell_stride`-th of them.
    FarFieldTable(const YarnDescription& d, const BysdfParams& material, const MultiscaleSettings& s,
                  int queries = 96, int cell_stride = 2);

    int classes() const { return classes_; }        // ply-colour classes
    int groups() const { return 2 + 2 * classes_; }  // spec R, spec T, body R per class, body T per class
    // Integrand f |cos| (1/sr) of lobe group g at node j, cell c, given a hit: without the lobe's
    // own albedo, with the plies crossed (per channel).
    Vec3 value(int node, int cell, int g) const {
        const float* v = &values_[((size_t(node) * kCells + cell) * groups() + g) * 3];
        return {v[0], v[1], v[2]};
    }
    float pass_fraction(int node) const { return pass_[node]; }
    // Integral over the sphere of group g at node j (its albedo given a hit, channel mean).
    float albedo(int node, int g) const { return albedo_[size_t(node) * groups() + g]; }
    // Sampling densities over the cells in (phi, sin theta_i) in [0, 1)^2: 0 specular, 1 body.
    const Distribution2D& distribution(int node, int kind) const { return distributions_[node * 2 + kind]; }
    size_t memory_bytes() const;
    double build_seconds() const { return build_seconds_; }

    // Node position of sin theta_o: nodes j0, j1 and the weight of j1.
    static void node_weights(float sin_o, int& j0, int& j1, float& t);
    // Cell of a local direction (x = yarn tangent), relative to the azimuth phi_o.
    static int cell_of(Vec3 wi, float phi_o);

private:
    int classes_ = 1;
    std::vector<float> values_, pass_, albedo_;
    std::vector<Distribution2D> distributions_;
    double build_seconds_ = 0;
};

// The table for this description and material (its colours count through the plies crossed),
// built on first use and kept for the process (the last few keys). Thread-safe; prints a
// progress line to stderr when a build takes more than a second.
std::shared_ptr<const FarFieldTable> far_field_table(const YarnDescription& d, const BysdfParams& material,
                                                     const MultiscaleSettings& s);

// Tabulations under way in this process: view angles done and to do over all of them (both 0
// when none runs), so front ends can show a table's build as progress instead of a stall.
struct FarFieldBuildProgress {
    int done = 0, total = 0;
};
FarFieldBuildProgress far_field_build_progress();

// The far field of one hit: the table with this curve's colours. Local frame: +x the yarn
// tangent, +z the view direction projected onto the normal plane (wo.y = 0 for the camera ray).
// eval returns f~ with f~ |wi.z| the tabulated integrand, so the renderer's f |cos| / pdf holds.
class FarFieldBsdf {
public:
    FarFieldBsdf(const FarFieldTable& table, const BysdfParams& colors);

    float pass_fraction(Vec3 wo) const;
    // The table holds the attenuated integrand: the shading point's exit is not needed.
    Vec3 eval(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return evaluate(wo, wi).f; }
    float pdf(Vec3 wo, Vec3 wi) const { return evaluate(wo, wi).pdf; }
    BsdfEvalPdf eval_pdf(Vec3 wo, Vec3 wi, const ScatterExit& = {}) const { return evaluate(wo, wi); }
    // u_lobe picks the theta_o node and then specular or body; u the cell and the point in it.
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u) const;
    std::optional<BsdfSample> sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery*) const { return sample(wo, u_lobe, u); }

private:
    BsdfEvalPdf evaluate(Vec3 wo, Vec3 wi) const;
    float specular_share(int node) const;  // probability of sampling the specular distribution
    Vec3 value(int node, int cell) const;

    const FarFieldTable* table_;
    Vec3 coef_[2 + 2 * kMaxPlyColors];  // per lobe group: the colours the table left out
};

}  // namespace purl
