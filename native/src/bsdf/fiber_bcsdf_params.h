// Parameters of the fiber scattering function of Khungurn et al. 2015 ("Matching Real Fabrics
// with Micro-Appearance Models"), shading every explicit fiber of the fiber-based reference.
// Declared once in fiber_bcsdf_param_table(): name, unit, range, default and meaning; the JSON
// reader ("fiber": {...} in a material), Python and docs/parameters.md derive from it.
//
// Units: lobe widths are standard deviations in degrees (as published); colours are linear
// Rec.709 in [0, 1]. The reflection colour is the Schlick reflectance at normal incidence.
#pragma once
#include <string>
#include <vector>

#include "base/param_info.h"
#include "math/vec.h"

namespace purl {

struct FiberBcsdfParams {
    Vec3 reflection_color;                  // A_R: Schlick F0 of the R lobe, per channel
    Vec3 transmission_color;                // A_TT: colour of the TT lobe
    float reflection_width;                 // beta_R: longitudinal width of R, degrees
    float transmission_width;               // beta_TT: longitudinal width of TT, degrees
    float transmission_azimuthal_width;     // gamma_TT: azimuthal width of TT, degrees
};

const std::vector<ParamInfo>& fiber_bcsdf_param_table();

// The table's defaults (the "fleece" fit).
FiberBcsdfParams default_fiber_bcsdf_params();

// Khungurn et al.'s fits (REFERENCE.md section 3): fleece, gabardine, silk, cotton, polyester.
// Throws InputError for other names.
FiberBcsdfParams fiber_bcsdf_preset(const std::string& name);
std::vector<std::string> fiber_bcsdf_preset_names();

// Throws InputError(file, place + "." + name, reason) for a NaN or out-of-range field.
void check_fiber_bcsdf_params(const FiberBcsdfParams& p, const std::string& file, const std::string& place);

}  // namespace purl
