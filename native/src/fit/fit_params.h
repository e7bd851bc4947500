// Which BYSDF parameters a fit may change, and the unit cube the optimiser works in.
// A colour parameter contributes three unknowns (one per channel). Every unknown lives in
// [0, 1]: linear over its range, or logarithmic for extinctions, whose effect on the image
// is roughly logarithmic (exp(-sigma_t d)), so equal steps in u change the image alike.
#pragma once
#include <string>
#include <vector>

#include "bsdf/bysdf_params.h"

namespace purl {

struct FitUnknown {
    const ParamInfo* info = nullptr;
    int component = 0;      // 0..2 for colours
    std::string label;      // "body_reflection_albedo[1]" or "sigma_t_body"
    float lo = 0, hi = 1;   // the range searched (inside the declared range)
    bool logarithmic = false;

    float value_at(double u) const;     // parameter value at u in [0, 1]
    double u_of(float value) const;     // inverse, clamped to [0, 1]
    float get(const BysdfParams& p) const;
    void set(BysdfParams& p, float value) const;
};

// The default list of fitted parameters: "kxB,kyB,sigma_t".
const char* default_fit_parameter_list();

// Comma-separated names of bysdf_param_table() entries or the paper's symbols
// (r, B, kxB, kyB, kxS, kyS, sigma_t = sigma_t_body, sigma_tS, eta, ...). Throws InputError
// naming `source` for an unknown or repeated name.
std::vector<FitUnknown> parse_fit_parameters(const std::string& list, const std::string& source);

// Short names accepted by parse_fit_parameters, "alias=name" each, for help texts.
std::vector<std::string> fit_parameter_aliases();

}  // namespace purl
