#include "fit/fit_params.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "base/input_error.h"

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

// Effective lobe albedos: name and the albedo parameter each one scales.
struct LobeAlias {
    const char* name;
    const char* albedo;
};
constexpr LobeAlias kLobes[4] = {{"axS", "specular_reflection_albedo"},
                                 {"ayS", "specular_transmission_albedo"},
                                 {"axB", "body_reflection_albedo"},
                                 {"ayB", "body_transmission_albedo"}};

float max_channel(Vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

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

LobeEnergies lobe_energies(const BysdfParams& p) {
    const float spec = 1 - p.body_share, r = p.body_reflection_share;
    return {{p.specular_reflection_albedo * spec, p.specular_transmission_albedo * spec,
             p.body_reflection_albedo * (r * p.body_share), p.body_transmission_albedo * ((1 - r) * p.body_share)}};
}

void set_lobe_energies(BysdfParams& p, const LobeEnergies& energies) {
    LobeEnergies e = energies;
    for (Vec3& v : e.e) v = Vec3(std::clamp(v.x, 0.0f, 1.0f), std::clamp(v.y, 0.0f, 1.0f), std::clamp(v.z, 0.0f, 1.0f));
    const float spec = std::max(max_channel(e.e[0]), max_channel(e.e[1]));
    float body_x = max_channel(e.e[2]), body_y = max_channel(e.e[3]);
    const float total = spec + body_x + body_y;
    if (total > 1) {  // the model cannot give more than all its energy
        for (Vec3& v : e.e) v = v / total;
        body_x /= total;
        body_y /= total;
    }
    // B and r0 as small as the body lobes allow; the specular albedos take what 1 - B leaves.
    const float body = std::max(body_x + body_y, 1e-6f);
    p.body_share = std::min(body, 1.0f);
    p.body_reflection_share = body_x + body_y > 0 ? body_x / (body_x + body_y) : p.body_reflection_share;
    const float spec_share = std::max(1 - p.body_share, 1e-6f);
    p.specular_reflection_albedo = e.e[0] / spec_share;
    p.specular_transmission_albedo = e.e[1] / spec_share;
    if (body_x > 0) p.body_reflection_albedo = e.e[2] / body_x;
    else p.body_reflection_albedo = Vec3(0.0f);
    if (body_y > 0) p.body_transmission_albedo = e.e[3] / body_y;
    else p.body_transmission_albedo = Vec3(0.0f);
    for (Vec3* v : {&p.specular_reflection_albedo, &p.specular_transmission_albedo})
        *v = Vec3(std::min(v->x, 1.0f), std::min(v->y, 1.0f), std::min(v->z, 1.0f));
}

float FitUnknown::get(const BysdfParams& p) const {
    if (lobe >= 0) {
        const LobeEnergies e = lobe_energies(p);
        return (&e.e[lobe].x)[component];
    }
    return param_field(p, *info)[component];
}
void FitUnknown::set(BysdfParams& p, float value) const { param_field(p, *info)[component] = value; }

BysdfParams apply_unknowns(const BysdfParams& start, const std::vector<FitUnknown>& unknowns,
                           const std::vector<float>& values) {
    BysdfParams p = start;
    bool lobes = false;
    for (size_t k = 0; k < unknowns.size(); ++k)
        if (unknowns[k].lobe < 0) unknowns[k].set(p, values[k]);
        else lobes = true;
    if (lobes) {
        LobeEnergies e = lobe_energies(p);
        for (size_t k = 0; k < unknowns.size(); ++k)
            if (unknowns[k].lobe >= 0) (&e.e[unknowns[k].lobe].x)[unknowns[k].component] = values[k];
        set_lobe_energies(p, e);
    }
    return p;
}

// Not r: r k_x^B and (1 - r) k_y^B scale the body lobes, so r and both albedos are not independent.
const char* default_fit_parameter_list() { return "kxB,kyB,sigma_t"; }

std::vector<std::string> fit_parameter_aliases() {
    std::vector<std::string> out;
    for (const auto& [alias, name] : aliases()) out.push_back(alias + "=" + name);
    for (const LobeAlias& l : kLobes) out.push_back(std::string(l.name) + "=effective " + l.albedo);
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
        int lobe = kNoLobe;
        for (int l = 0; l < 4; ++l)
            if (name == kLobes[l].name) lobe = l;
        if (lobe >= 0) {
            const std::string lobe_name = name;
            for (const ParamInfo& p : bysdf_param_table())
                if (p.name == std::string(kLobes[lobe].albedo)) {
                    if (!seen.insert(lobe_name).second)
                        throw InputError(source, "\"" + lobe_name + "\"", "is listed twice");
                    for (int c = 0; c < 3; ++c) {
                        FitUnknown u;
                        u.info = &p;
                        u.lobe = lobe;
                        u.component = c;
                        u.label = lobe_name + "[" + std::to_string(c) + "]";
                        unknowns.push_back(u);
                    }
                }
            continue;
        }
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
    // A lobe energy already sets B, r and its own albedo: naming them too gives the fit a
    // direction that changes nothing.
    bool any_lobe = false;
    for (const FitUnknown& u : unknowns) any_lobe |= u.lobe >= 0;
    if (any_lobe)
        for (const FitUnknown& u : unknowns) {
            if (u.lobe >= 0) continue;
            const std::string n = u.info->name;
            bool clash = n == "body_share" || n == "body_reflection_share";
            for (const LobeAlias& l : kLobes) clash |= n == l.albedo;
            if (clash)
                throw InputError(source, "\"" + n + "\"",
                                 "is set by the lobe energies (axS, ayS, axB, ayB) already; fit one or the other");
        }
    return unknowns;
}

}  // namespace purl
