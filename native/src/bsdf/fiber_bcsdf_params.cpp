#include "bsdf/fiber_bcsdf_params.h"

#include <cstddef>

#include "math/number_text.h"
#include "base/input_error.h"

namespace purl {
namespace {

// One published fit (Khungurn et al. 2015; REFERENCE.md section 3). Their fiber count per ply,
// rho and alpha describe the fitted fiber geometry; Purl's fibers come from the yarn
// description instead, so only the optical terms are used.
struct Fit {
    const char* name;
    Vec3 r_color, tt_color;
    float r_width, tt_width, tt_azimuthal;  // degrees
};
const Fit kFits[] = {
    {"fleece", {0.040f, 0.087f, 0.087f}, {0.452f, 0.725f, 0.948f}, 7.238f, 10.0f, 25.989f},
    {"gabardine", {0.185f, 0.047f, 0.069f}, {0.999f, 0.330f, 0.354f}, 2.141f, 10.0f, 23.548f},
    {"silk", {0.745f, 0.008f, 0.070f}, {0.620f, 0.553f, 0.562f}, 1.000f, 10.0f, 19.823f},
    {"cotton", {0.989f, 0.959f, 0.874f}, {0.999f, 0.999f, 0.999f}, 1.000f, 27.197f, 38.269f},
    {"polyester", {0.700f, 0.700f, 0.700f}, {0.600f, 0.000f, 0.800f}, 5.238f, 10.0f, 25.000f},
};

std::vector<ParamInfo> build_table() {
    const Fit& d = kFits[0];
    auto color = [](const char* name, Vec3 def, const char* doc, size_t offset) {
        return ParamInfo{name, "", 3, 0.0f, 1.0f, {def.x, def.y, def.z}, doc, offset, true};
    };
    auto width = [](const char* name, float hi, float def, const char* doc, size_t offset) {
        return ParamInfo{name, "deg", 1, 0.5f, hi, {def, 0, 0}, doc, offset, false};
    };
    return {
        color("reflection_color", d.r_color,
              "A_R: Schlick reflectance at normal incidence of the fiber's surface reflection (R lobe).",
              offsetof(FiberBcsdfParams, reflection_color)),
        color("transmission_color", d.tt_color,
              "A_TT: colour of the light transmitted through the fiber (TT lobe).",
              offsetof(FiberBcsdfParams, transmission_color)),
        width("reflection_width", 60.0f, d.r_width,
              "beta_R: standard deviation of the R lobe around the specular cone, in degrees.",
              offsetof(FiberBcsdfParams, reflection_width)),
        width("transmission_width", 60.0f, d.tt_width,
              "beta_TT: standard deviation of the TT lobe around the specular cone, in degrees.",
              offsetof(FiberBcsdfParams, transmission_width)),
        width("transmission_azimuthal_width", 180.0f, d.tt_azimuthal,
              "gamma_TT: standard deviation of the TT lobe around the forward azimuth, in degrees.",
              offsetof(FiberBcsdfParams, transmission_azimuthal_width)),
    };
}

}  // namespace

const std::vector<ParamInfo>& fiber_bcsdf_param_table() {
    static const std::vector<ParamInfo> table = build_table();
    return table;
}

FiberBcsdfParams default_fiber_bcsdf_params() {
    FiberBcsdfParams p;
    apply_defaults(p, fiber_bcsdf_param_table());
    return p;
}

FiberBcsdfParams fiber_bcsdf_preset(const std::string& name) {
    for (const Fit& f : kFits)
        if (name == f.name) return {f.r_color, f.tt_color, f.r_width, f.tt_width, f.tt_azimuthal};
    std::string known;
    for (const Fit& f : kFits) known += (known.empty() ? "" : ", ") + std::string(f.name);
    throw InputError("", "fiber preset \"" + name + "\"", "unknown; known presets: " + known);
}

std::vector<std::string> fiber_bcsdf_preset_names() {
    std::vector<std::string> names;
    for (const Fit& f : kFits) names.push_back(f.name);
    return names;
}

void check_fiber_bcsdf_params(const FiberBcsdfParams& p, const std::string& file, const std::string& place) {
    for (const ParamInfo& info : fiber_bcsdf_param_table()) {
        const float* v = param_field(p, info);
        for (int c = 0; c < info.components; ++c)
            if (!(v[c] >= info.min_value && v[c] <= info.max_value))  // also catches NaN
                throw InputError(file, place + "." + info.name,
                                 "value " + number_text(v[c]) + " outside [" + number_text(info.min_value) +
                                     ", " + number_text(info.max_value) + "]");
    }
}

}  // namespace purl
