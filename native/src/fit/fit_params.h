// Which BYSDF parameters a fit may change, and the unit cube the optimiser works in.
// A colour parameter contributes three unknowns (one per channel). Every unknown lives in
// [0, 1]: linear over its range, or logarithmic for extinctions, whose effect on the image
// is roughly logarithmic (exp(-sigma_t d)), so equal steps in u change the image alike.
#pragma once
#include <string>
#include <vector>

#include "bsdf/bysdf_params.h"

namespace purl {

// Effective lobe albedos, what the image actually depends on: (1-B) k_x^S, (1-B) k_y^S,
// r0 B k_x^B, (1-r0) B k_y^B. Fitting these instead of B, r and the four albedos removes the
// directions along which the image does not change.
enum FitLobe { kNoLobe = -1, kLobeSpecularReflection, kLobeSpecularTransmission, kLobeBodyReflection,
               kLobeBodyTransmission };
struct LobeEnergies {
    Vec3 e[4];
};
LobeEnergies lobe_energies(const BysdfParams& p);
// Chooses B, r0 and the four albedos that give `e` (largest channel of each body albedo 1);
// when the lobes ask for more than 1 in all, they are scaled down together.
void set_lobe_energies(BysdfParams& p, const LobeEnergies& e);

struct FitUnknown {
    const ParamInfo* info = nullptr;  // the parameter, or for a lobe energy the lobe's albedo
    int lobe = kNoLobe;     // >= 0: an effective lobe albedo (FitLobe), set through set_lobe_energies
    int component = 0;      // 0..2 for colours
    std::string label;      // "body_reflection_albedo[1]" or "sigma_t_body"
    float lo = 0, hi = 1;   // the range searched (inside the declared range)
    bool logarithmic = false;

    float value_at(double u) const;     // parameter value at u in [0, 1]
    double u_of(float value) const;     // inverse, clamped to [0, 1]
    float get(const BysdfParams& p) const;
    void set(BysdfParams& p, float value) const;  // plain parameters only (lobe < 0)
};

// `start` with every unknown set to its value (lobe energies together, after the others).
BysdfParams apply_unknowns(const BysdfParams& start, const std::vector<FitUnknown>& unknowns,
                           const std::vector<float>& values);

// The default list of fitted parameters: "kxB,kyB,sigma_t".
const char* default_fit_parameter_list();

// Comma-separated names of bysdf_param_table() entries, the paper's symbols (r, B, kxB, kyB,
// kxS, kyS, sigma_t = sigma_t_body, sigma_tS, eta, ...) or the lobe energies axS, ayS, axB,
// ayB. Throws InputError naming `source` for an unknown or repeated name, or for a list that
// names a lobe energy together with B, r or that lobe's albedo (the same lobe twice).
std::vector<FitUnknown> parse_fit_parameters(const std::string& list, const std::string& source);

// Short names accepted by parse_fit_parameters, "alias=name" each, for help texts.
std::vector<std::string> fit_parameter_aliases();

}  // namespace purl
