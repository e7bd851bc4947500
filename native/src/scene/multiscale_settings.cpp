#include "scene/multiscale_settings.h"

#include <cmath>
#include <cstddef>

#include "base/input_error.h"
#include "base/registry.h"
#include "math/number_text.h"

namespace purl {
namespace {

ParamInfo scalar(const char* name, const char* unit, float lo, float hi, float def, const char* doc,
                 size_t offset) {
    return {name, unit, 1, lo, hi, {def, 0, 0}, doc, offset, false};
}

ParamInfo whole(const char* name, const char* unit, float lo, float hi, float def, const char* doc, size_t offset) {
    ParamInfo info = scalar(name, unit, lo, hi, def, doc, offset);
    info.kind = ParamKind::Integer;
    return info;
}

std::vector<ParamInfo> build_table() {
    return {
        scalar("multiscale_roughness_c", "", 0.25f, 1e6f, 64.0f,
               "C in beta_multi = beta + (h2 - h1) / C: how much a wide footprint roughens the specular lobes.",
               offsetof(MultiscaleSettings, roughness_c)),
        scalar("multiscale_footprint_scale", "px", 0.0f, 16.0f, 1.0f,
               "Pixel footprint used for the h range, in pixels (0 turns multi-scale into near field).",
               offsetof(MultiscaleSettings, footprint_scale)),
        whole("multiscale_max_h_samples", "", 1.0f, float(kMaxHSamples), 5.0f,
              "Most azimuthal offsets h traced per camera hit (a whole number; more cost more than they save).",
              offsetof(MultiscaleSettings, max_h_samples)),
        scalar("multiscale_sample_spacing", "fibers", 0.25f, 64.0f, 1.0f,
               "Footprint width per h sample, in fiber diameters.",
               offsetof(MultiscaleSettings, sample_spacing)),
        scalar("multiscale_near_limit", "fibers", 0.0f, 64.0f, 1.0f,
               "Auto mode shades the near field when the footprint covers fewer fiber diameters than this.",
               offsetof(MultiscaleSettings, near_limit)),
        scalar("multiscale_near_pixels", "px", 0.0f, 1024.0f, 4.0f,
               "Auto mode shades the near field on yarns at least this many pixels wide: the pixel resolves "
               "their plies, and pixel samples average their fibers as cheaply as traced h samples (0: off).",
               offsetof(MultiscaleSettings, near_pixels)),
        scalar("multiscale_far_limit", "yarns", 0.25f, 64.0f, 1.0f,
               "Auto mode shades the tabulated far field when one pixel spans at least this many yarn diameters.",
               offsetof(MultiscaleSettings, far_limit)),
    };
}

}  // namespace

const std::vector<ParamInfo>& multiscale_param_table() {
    static const std::vector<ParamInfo> table = build_table();
    return table;
}

MultiscaleSettings default_multiscale_settings() {
    MultiscaleSettings s{};
    apply_defaults(s, multiscale_param_table());
    return s;
}

void check_multiscale_settings(const MultiscaleSettings& s, const std::string& file, const std::string& place) {
    for (const ParamInfo& info : multiscale_param_table()) {
        const float v = *param_field(s, info);
        if (!(v >= info.min_value && v <= info.max_value))
            throw InputError(file, place + "." + info.name,
                             "value " + number_text(v) + " outside [" + number_text(info.min_value) + ", " +
                                 number_text(info.max_value) + "]");
        if (info.is_integer() && v != std::floor(v))
            throw InputError(file, place + "." + info.name, "must be a whole number");
    }
}

// Names and order come from base/registry.h, whose values are these enums'.
const char* multiscale_mode_name(MultiscaleMode mode) {
    return choice_name(multiscale_modes(), float(mode));
}

std::optional<MultiscaleMode> parse_multiscale_mode(const std::string& name) {
    const Choice* c = find_choice(multiscale_modes(), name);
    if (!c) return std::nullopt;
    return static_cast<MultiscaleMode>(c->value);
}

const char* multiscale_aggregation_name(MultiscaleAggregation a) {
    return choice_name(multiscale_aggregations(), float(a));
}

std::optional<MultiscaleAggregation> parse_multiscale_aggregation(const std::string& name) {
    const Choice* c = find_choice(multiscale_aggregations(), name);
    if (!c) return std::nullopt;
    return static_cast<MultiscaleAggregation>(c->value);
}

}  // namespace purl
