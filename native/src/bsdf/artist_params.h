// The artist's controls of a BYSDF material, as Principled Hair gives hair a colour and a few
// sliders over its physics: yarn colour, sheen, softness and translucency. Each is declared
// once in artist_param_table() (name, label, range, neutral default, and the rule that maps it
// onto the BYSDF parameters), and apply_artist_controls() is that rule. The scene reader
// (a bysdf material's "color", "sheen", ...), purlcore.artist_parameters() /
// purlcore.resolve_material() and the Blender Yarn panel derive from the table.
//
// The controls act on top of the physics parameters (a preset or a fit) and are neutral at their
// defaults, so a preset keeps its measured values until an artist moves a control, and choosing
// another preset keeps the artist's colour. docs/artist-controls.md.
#pragma once
#include <string>
#include <vector>

#include "bsdf/bysdf_params.h"
#include "base/param_info.h"
#include "math/vec.h"

namespace purl {

struct ArtistControls {
    Vec3 color{1.0f};          // yarn colour (linear RGB); used only when has_color
    float sheen = 1.0f;        // x the specular share 1 - B
    float softness = 1.0f;     // x the specular reflection's GGX roughness
    float translucency = 1.0f; // x the forward-scattered body share 1 - r0, / the body extinction
    bool has_color = false;    // "color" given: replaces the hue of both body albedos
};

const std::vector<ParamInfo>& artist_param_table();

// The BYSDF parameters `physics` with the controls applied (neutral controls return them as
// they are). Rules, in order:
//   colour c:         k_x^B = c max(k_x^B), k_y^B = c max(k_y^B)  (each lobe keeps its strength)
//   sheen s:          1 - B = min(1, (1 - B) s)                   (energy moves body <-> specular)
//   softness f:       alpha_along, alpha_across = clamp(alpha f, 0.001, 1)
//   translucency t:   1 - r0 = min(1, (1 - r0) t); sigma_t_body = min(1000, sigma_t_body / t)
BysdfParams apply_artist_controls(const BysdfParams& physics, const ArtistControls& controls);

}  // namespace purl
