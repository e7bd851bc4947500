#include "bsdf/artist_params.h"

#include <algorithm>
#include <cstddef>

namespace purl {
namespace {

constexpr float kMaxExtinction = 1000.0f;  // the table's upper bound of sigma_t_body
constexpr float kMinAlpha = 0.001f;        // the table's lower bound of the GGX roughness

ParamInfo control(const char* label, const char* name, float hi, const char* doc, size_t offset) {
    return labelled({name, "", 1, 0.0f, hi, {1.0f, 0, 0}, doc, offset, false}, label);
}

std::vector<ParamInfo> build_table() {
    return {
        labelled({"color", "", 3, 0.0f, 1.0f, {1.0f, 1.0f, 1.0f},
                  "Yarn colour: replaces the hue of both body albedos, each keeping its own strength (its "
                  "largest channel), so a preset's measured lobe strengths stay as they are.",
                  offsetof(ArtistControls, color), true},
                 "Yarn Colour"),
        control("Sheen", "sheen", 2.0f,
                "Multiplies the share of light the specular (shiny) lobes take, 1 - B, capped at 1; the body "
                "lobes take the rest. 0 is matte, 1 is the material as measured.",
                offsetof(ArtistControls, sheen)),
        control("Softness", "softness", 4.0f,
                "Multiplies the roughness of the specular reflection along and across the fibers: above 1 the "
                "sheen spreads wider and softer, below 1 it tightens.",
                offsetof(ArtistControls, softness)),
        control("Translucency", "translucency", 2.0f,
                "Multiplies the share of the body light scattered forward through the yarn, 1 - r0 (capped at "
                "1), and divides the body extinction by the same factor. 0 makes the yarn opaque.",
                offsetof(ArtistControls, translucency)),
    };
}

}  // namespace

const std::vector<ParamInfo>& artist_param_table() {
    static const std::vector<ParamInfo> table = build_table();
    return table;
}

BysdfParams apply_artist_controls(const BysdfParams& physics, const ArtistControls& a) {
    BysdfParams p = a.has_color ? with_body_color(physics, a.color) : physics;
    if (a.sheen != 1.0f) p.body_share = 1.0f - std::min(1.0f, (1.0f - p.body_share) * std::max(a.sheen, 0.0f));
    if (a.softness != 1.0f) {
        const float f = std::max(a.softness, 0.0f);
        p.specular_roughness_along = clamp(p.specular_roughness_along * f, kMinAlpha, 1.0f);
        p.specular_roughness_across = clamp(p.specular_roughness_across * f, kMinAlpha, 1.0f);
    }
    if (a.translucency != 1.0f) {
        const float t = std::max(a.translucency, 0.0f);
        p.body_reflection_share = 1.0f - std::min(1.0f, (1.0f - p.body_reflection_share) * t);
        p.sigma_t_body = t > 0 ? std::min(kMaxExtinction, p.sigma_t_body / t) : kMaxExtinction;
    }
    return p;
}

}  // namespace purl
