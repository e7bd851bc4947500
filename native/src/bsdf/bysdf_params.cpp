#include "bsdf/bysdf_params.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "base/input_error.h"
#include "base/registry.h"
#include "math/number_text.h"

namespace purl {
namespace {

ParamInfo scalar(const char* label, const char* name, const char* unit, float lo, float hi, float def,
                 const char* doc, size_t offset) {
    return labelled({name, unit, 1, lo, hi, {def, 0, 0}, doc, offset, false}, label);
}
ParamInfo color(const char* label, const char* name, Vec3 def, const char* doc, size_t offset) {
    return labelled({name, "", 3, 0.0f, 1.0f, {def.x, def.y, def.z}, doc, offset, true}, label);
}

std::vector<ParamInfo> build_table() {
    // Defaults follow the authors' prototype (REFERENCE.md section 1), converted to our
    // units: its extinction 5.5 and 0.1 per scene unit at yarn radius 2 are 11 and 0.2 per R.
    const Vec3 body_x(0.045f, 0.015f, 0.0f);
    std::vector<ParamInfo> t = {
        scalar("Fiber IOR", "eta", "", kFiberEta.min, kFiberEta.max, 1.5f,
               "Refractive index of the fiber material relative to air.", offsetof(BysdfParams, eta)),
        scalar("Roughness Along", "specular_roughness_along", "", 0.001f, 1.0f, 0.2f,
               "GGX alpha of the specular reflection f_x^S along the fiber tangent.",
               offsetof(BysdfParams, specular_roughness_along)),
        scalar("Roughness Across", "specular_roughness_across", "", 0.001f, 1.0f, 0.3f,
               "GGX alpha of the specular reflection f_x^S across the fiber.",
               offsetof(BysdfParams, specular_roughness_across)),
        scalar("Transmission Roughness", "transmission_roughness", "", 0.001f, 1.0f, 0.9f,
               "GGX alpha of the specular transmission f_y^S (isotropic).",
               offsetof(BysdfParams, transmission_roughness)),
        color("Specular Tint", "specular_reflection_albedo", Vec3(1.0f),
              "Specular albedo k_x^S that tints the Fresnel reflection.",
              offsetof(BysdfParams, specular_reflection_albedo)),
        color("Transmission Tint", "specular_transmission_albedo", Vec3(1.0f),
              "Specular albedo k_y^S that tints the rough transmission through the yarn.",
              offsetof(BysdfParams, specular_transmission_albedo)),
        scalar("Body Share", "body_share", "", 0.0f, 1.0f, 0.5f,
               "B: share of the energy given to the body lobes; the specular lobes get 1 - B.",
               offsetof(BysdfParams, body_share)),
        scalar("Backscatter Share", "body_reflection_share", "", 0.0f, 1.0f, 0.5f,
               "r0: share of the body energy scattered back (f_x^B) rather than forward (f_y^B).",
               offsetof(BysdfParams, body_reflection_share)),
        scalar("Backscatter Fresnel", "body_reflection_fresnel", "", 0.0f, 1.0f, 0.0f,
               "Blend of r from r0 (0) toward the Fresnel reflectance at the viewing angle (1).",
               offsetof(BysdfParams, body_reflection_fresnel)),
        color("Backscatter Albedo", "body_reflection_albedo", body_x, "Body albedo k_x^B of the back-scattered body lobe.",
              offsetof(BysdfParams, body_reflection_albedo)),
        color("Forward Albedo", "body_transmission_albedo", body_x * 6.0f,
              "Body albedo k_y^B of the forward-scattered body lobe.",
              offsetof(BysdfParams, body_transmission_albedo)),
        scalar("Lommel-Seeliger", "lommel_seeliger_weight", "", 0.0f, 1.0f, 1.0f,
               "Weight of the Lommel-Seeliger term next to the Lambertian term in f_x^B.",
               offsetof(BysdfParams, lommel_seeliger_weight)),
        scalar("Extinction Specular", "sigma_t_specular", "1/R", 0.0f, 1000.0f, 11.0f,
               "Extinction of the specular transmission, per yarn radius of path length.",
               offsetof(BysdfParams, sigma_t_specular)),
        scalar("Extinction Body", "sigma_t_body", "1/R", 0.0f, 1000.0f, 0.2f,
               "Extinction of the body transmission, per yarn radius of path length.",
               offsetof(BysdfParams, sigma_t_body)),
        scalar("Ply Shadow Floor", "ply_shadow_floor", "", 0.0f, 1.0f, 0.6f,
               "Lowest value the ply self-shadowing G_p may take.", offsetof(BysdfParams, ply_shadow_floor)),
        scalar("Fiber Shadow Floor", "fiber_shadow_floor", "", 0.0f, 1.0f, 0.5f,
               "Lowest value the fiber self-shadowing G_f may take.",
               offsetof(BysdfParams, fiber_shadow_floor)),
    };
    ParamInfo ply_crossing = scalar(
        "Ply Crossing", "ply_crossing", "", 0.0f, 2.0f, 1.0f,
        "How light crosses the other plies: 0 the paper's tau^N_i over the yarn chord and the G_p map, "
        "1 traced through the implicit plies on the way out (their extinction and transmission albedo), "
        "2 traced and spread: light that another ply scattered arrives diffuse, from around the ray.",
        offsetof(BysdfParams, ply_crossing));
    ply_crossing.kind = ParamKind::Integer;
    t.push_back(ply_crossing);
    ParamInfo ply_color_count = scalar("Ply Colours", "ply_color_count", "", 1.0f, float(kMaxPlyColors), 1.0f,
                                       "Number of ply colours in use; ply i takes ply colour (i mod count) + 1.",
                                       offsetof(BysdfParams, ply_color_count));
    ply_color_count.kind = ParamKind::Integer;
    t.push_back(ply_color_count);
    // String literals keep the names alive for the table's lifetime.
    static const char* const names[kMaxPlyColors] = {
        "ply_color_1", "ply_color_2", "ply_color_3", "ply_color_4",  "ply_color_5",  "ply_color_6",
        "ply_color_7", "ply_color_8", "ply_color_9", "ply_color_10", "ply_color_11", "ply_color_12"};
    static const char* const labels[kMaxPlyColors] = {"Ply 1", "Ply 2", "Ply 3", "Ply 4",  "Ply 5",  "Ply 6",
                                                      "Ply 7", "Ply 8", "Ply 9", "Ply 10", "Ply 11", "Ply 12"};
    for (int i = 0; i < kMaxPlyColors; ++i)
        t.push_back(color(labels[i], names[i], Vec3(1.0f), "Multiplies both body albedos on the plies using this colour.",
                          offsetof(BysdfParams, ply_colors) + i * sizeof(Vec3)));
    return t;
}

}  // namespace

const std::vector<ParamInfo>& bysdf_param_table() {
    static const std::vector<ParamInfo> table = build_table();
    return table;
}

Vec3 recolored_albedo(Vec3 albedo, Vec3 color) {
    const float strength = std::max(albedo.x, std::max(albedo.y, albedo.z));
    const Vec3 c(std::clamp(color.x, 0.0f, 1.0f), std::clamp(color.y, 0.0f, 1.0f), std::clamp(color.z, 0.0f, 1.0f));
    return c * std::clamp(strength, 0.0f, 1.0f);  // NaN passes through; Bysdf clamps its inputs
}

BysdfParams with_body_color(const BysdfParams& params, Vec3 color) {
    BysdfParams p = params;
    p.body_reflection_albedo = recolored_albedo(params.body_reflection_albedo, color);
    p.body_transmission_albedo = recolored_albedo(params.body_transmission_albedo, color);
    return p;
}

BysdfParams default_bysdf_params() {
    BysdfParams p;
    apply_defaults(p, bysdf_param_table());
    return p;
}

void check_bysdf_params(const BysdfParams& p, const std::string& file, const std::string& place) {
    for (const ParamInfo& info : bysdf_param_table()) {
        const float* v = param_field(p, info);
        for (int c = 0; c < info.components; ++c) {
            if (!(v[c] >= info.min_value && v[c] <= info.max_value))  // also catches NaN
                throw InputError(file, place + "." + info.name,
                                 "value " + number_text(v[c]) + " outside [" +
                                     number_text(info.min_value) + ", " + number_text(info.max_value) + "]");
        }
        if (info.is_integer() && v[0] != std::floor(v[0]))
            throw InputError(file, place + "." + info.name, "must be a whole number");
    }
}

}  // namespace purl
