// Settings of the multi-scale BYSDF (render/multiscale.h): the shading mode and the float
// parameters of multiscale_param_table(). They live in scene/ because they are part of a
// scene's render settings (JSON "render": {"multiscale": {...}}), which render/ reads.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "base/param_info.h"

namespace purl {

// near: the BYSDF at the hit point; multi: averaged over the pixel footprint across the yarn;
// far: averaged over the whole yarn width; auto: per camera hit, the cheapest accurate one.
enum class MultiscaleMode { Near, Multi, Far, Auto };
enum class MultiscaleAggregation { Mixture, Aggregate };

constexpr int kMaxHSamples = 16;

struct MultiscaleSettings {
    MultiscaleMode mode = MultiscaleMode::Auto;
    MultiscaleAggregation aggregation = MultiscaleAggregation::Mixture;
    // Float fields, declared in multiscale_param_table():
    float roughness_c;       // C_beta in beta_multi = beta + (h2 - h1) / C_beta; dimensionless
    float footprint_scale;   // pixels: multiplies the one-pixel differentials
    float max_h_samples;     // whole number 1..16: most h samples per hit
    float sample_spacing;    // fiber diameters of footprint per h sample
    float near_limit;        // auto: near field below this many fiber diameters of footprint
    float near_pixels;       // auto: near field on yarns at least this many pixels wide
    float far_limit;         // auto: far field when a pixel spans at least this many yarn diameters
};

const std::vector<ParamInfo>& multiscale_param_table();
MultiscaleSettings default_multiscale_settings();
// Throws InputError(file, place + "." + name, reason) for NaN, out-of-range or fractional values.
void check_multiscale_settings(const MultiscaleSettings& s, const std::string& file, const std::string& place);

const char* multiscale_mode_name(MultiscaleMode mode);  // "near", "multi", "far", "auto"
std::optional<MultiscaleMode> parse_multiscale_mode(const std::string& name);
const char* multiscale_aggregation_name(MultiscaleAggregation a);  // "mixture", "aggregate"
std::optional<MultiscaleAggregation> parse_multiscale_aggregation(const std::string& name);

}  // namespace purl
