// The BYSDF's material parameters (Khattar et al. 2024, section 4.1), declared once in
// bysdf_param_table(): name, unit, range, default and a one-sentence meaning. The JSON
// reader, Python module, Blender UI and docs/bysdf.md derive from that table.
//
// Units: GGX roughness is the slope scale alpha (dimensionless); extinction is per yarn
// radius ("1/R"), so a preset does not change with scene scale: the renderer passes the
// chord |x - y| divided by the yarn radius. Colours are linear Rec.709 albedos in [0, 1].
#pragma once
#include <string>
#include <vector>

#include "base/param_info.h"
#include "math/vec.h"

namespace purl {

constexpr int kMaxPlyColors = 12;

// Vec3 fields are three contiguous floats, which is what the table's offsets address.
struct BysdfParams {
    float eta;                          // refractive index of the fibers (relative to air)
    float specular_roughness_along;     // f_x^S GGX alpha along the fiber tangent
    float specular_roughness_across;    // f_x^S GGX alpha across the fiber
    float transmission_roughness;       // f_y^S GGX alpha (isotropic)
    Vec3 specular_reflection_albedo;    // k_x^S
    Vec3 specular_transmission_albedo;  // k_y^S
    float body_share;                   // B: share of energy given to the body lobes
    float body_reflection_share;        // r0: reflected share of the body energy
    float body_reflection_fresnel;      // t: r = (1 - t) r0 + t F(cos theta_o)
    Vec3 body_reflection_albedo;        // k_x^B
    Vec3 body_transmission_albedo;      // k_y^B
    float lommel_seeliger_weight;       // w: weight of the LS term inside f_x^B
    float sigma_t_specular;             // extinction for f_y^S, 1/R
    float sigma_t_body;                 // extinction for f_y^B, 1/R
    float ply_shadow_floor;             // lower bound applied to G_p
    float fiber_shadow_floor;           // lower bound applied to G_f
    float ply_crossing;                 // 0: the paper's tau^N_i and G_p map; 1: traced through the plies; 2: traced, spread
    float ply_color_count;              // number of ply colours in use (integer 1..12)
    Vec3 ply_colors[kMaxPlyColors];     // body-albedo multipliers, ply i uses i % count
};

const std::vector<ParamInfo>& bysdf_param_table();

// The table's defaults.
BysdfParams default_bysdf_params();

// A curve's own colour (YarnCurves::colors) replaces the body colour of the material: each
// body albedo becomes `color` times its own largest channel, so the material still decides
// how bright the back- and forward-scattered body lobes are and the curve decides their hue
// and relative brightness. Ply colours keep multiplying on top; specular lobes are untouched.
// `color` is clamped to [0, 1].
BysdfParams with_body_color(const BysdfParams& params, Vec3 color);
// The same rule for any one albedo: `color` x the largest channel of `albedo`.
Vec3 recolored_albedo(Vec3 albedo, Vec3 color);

// Throws InputError(file, place + "." + name, reason) for a NaN or out-of-range field or a
// non-integer ply_color_count. For front doors that fill the struct without the JSON reader.
void check_bysdf_params(const BysdfParams& p, const std::string& file, const std::string& place);

}  // namespace purl
