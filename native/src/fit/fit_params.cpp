#include "fit/fit_params.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "scene/input_error.h"

namespace purl {
namespace {

// The paper's symbols (section 4.1) for the parameters one usually fits.
const std::vector<std::pair<std::string, std::string>>& aliases() {
    static const std::vector<std::pair<std::string, std::string>> table = {
        {"r", "body_reflection_share"},        {"B", "body_share"},
        {"kxB", "body_reflection_albedo"},     {"kyB", "body_transmission_albedo"},
        {"kxS", "specular_reflection_albedo"}, {"kyS", "specular_transmission_albedo"},
        {"sigma_t", "sigma_t_body"},           {"sigma_tS", "sigma_t_specular"},
        {"t", "body_reflection_fresnel"},      {"w", "lommel_seeliger_weight"},
        {"alpha_x", "specular_roughness_along"}, {"alpha_y", "specular_roughness_across"},
        {"alpha_t", "transmission_roughness"},
    };
    return table;
}

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    const size_t b = s.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

}  // namespace

float FitUnknown::value_at(double u) const {
    u = std::clamp(u, 0.0, 1.0);
    if (logarithmic) return float(std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo))));
    return float(lo + u * (hi - lo));
}

double FitUnknown::u_of(float value) const {
    double u;
    if (logarithmic) u = (std::log(std::max(value, lo)) - std::log(lo)) / (std::log(hi) - std::log(lo));
    else u = (double(value) - lo) / (double(hi) - lo);
    return std::clamp(u, 0.0, 1.0);
}

float FitUnknown::get(const BysdfParams& p) const { return param_field(p, *info)[component]; }
void FitUnknown::set(BysdfParams& p, float value) const { param_field(p, *info)[component] = value; }

// Not r: r k_x^B and (1 - r) k_y^B scale the body lobes, so r and both albedos are not independent.
const char* default_fit_parameter_list() { return "kxB,kyB,sigma_t"; }

std::vector<std::string> fit_parameter_aliases() {
    std::vector<std::string> out;
    for (const auto& [alias, name] : aliases()) out.push_back(alias + "=" + name);
    return out;
}

std::vector<FitUnknown> parse_fit_parameters(const std::string& list, const std::string& source) {
    std::vector<FitUnknown> unknowns;
    std::set<std::string> seen;
    size_t start = 0;
    while (start <= list.size()) {
        const size_t comma = std::min(list.find(',', start), list.size());
        std::string name = trim(list.substr(start, comma - start));
        start = comma + 1;
        if (name.empty()) continue;
        for (const auto& [alias, full] : aliases())
            if (name == alias) name = full;
        const ParamInfo* info = nullptr;
        for (const ParamInfo& p : bysdf_param_table())
            if (name == p.name) info = &p;
        if (!info) {
            std::string known;
            for (const auto& [alias, full] : aliases()) known += (known.empty() ? "" : ", ") + alias;
            throw InputError(source, "\"" + name + "\"",
                             "not a bysdf parameter (use a name from docs/parameters.md or one of " + known + ")");
        }
        if (std::string(info->name) == "ply_color_count")
            throw InputError(source, "\"" + name + "\"", "is a whole number and cannot be fitted");
        if (!seen.insert(info->name).second)
            throw InputError(source, "\"" + name + "\"", "is listed twice");
        for (int c = 0; c < info->components; ++c) {
            FitUnknown u;
            u.info = info;
            u.component = c;
            u.label = info->components == 1 ? info->name : std::string(info->name) + "[" + std::to_string(c) + "]";
            u.lo = info->min_value;
            u.hi = info->max_value;
            // Extinctions span orders of magnitude: search 0.01 .. 1000 per R logarithmically.
            if (std::string(info->unit) == "1/R") {
                u.logarithmic = true;
                u.lo = std::max(u.lo, 0.01f);
            }
            unknowns.push_back(u);
        }
    }
    if (unknowns.empty()) throw InputError(source, "", "no parameters to fit");
    return unknowns;
}

}  // namespace purl
