// Every choosable thing, declared once: the scattering models, the ply search methods, the
// multi-scale modes, the integrators and the render settings with their ranges and defaults.
// The JSON reader (scene/scene_json.cpp), the `purl` command's option checks and help, purlcore
// (render_settings(), choices()) and the Blender add-on all read these tables, and
// docs/parameters.md is generated from them (tools/gen_parameters_doc.py).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "base/param_info.h"

namespace purl {

// How the BYSDF finds the ply under a tube hit (render.ply_method; docs/implicit-geometry.md).
// The values are the enum's; names and order of the choice are ply_methods().
enum class PlyCrossSection {
    elliptical,  // plane through the ray, oriented by each ply's tangent (default)
    circular,    // perpendicular cross-section at the hit (Zhu et al. 2023; comparison only)
    local,       // as elliptical, on the yarn straightened to second order at the hit (fast)
};

struct Range {
    float min, max;
};
// The fiber's relative refractive index: the material table's range (bysdf_param_table) and
// the clamp the BYSDF applies to any value given without the reader (bsdf/bysdf.cpp).
inline constexpr Range kFiberEta{1.001f, 4.0f};

const ChoiceList& yarn_models();         // render.model: bysdf, ply, fiber
const ChoiceList& material_models();     // material.model: bysdf, placeholder, fiber
const ChoiceList& ply_methods();         // render.ply_method: elliptical, local, circular
const ChoiceList& multiscale_modes();    // render.multiscale.mode: near, multi, far, auto
const ChoiceList& multiscale_aggregations();  // render.multiscale.aggregation: mixture, aggregate
const ChoiceList& integrators();         // render.integrator: path, trace
const ChoiceList& twist_directions();    // ply_handedness, fiber_handedness: S (-1), Z (+1)
// Every list above, for front doors that show them all (purlcore.choices()).
std::vector<const ChoiceList*> all_choice_lists();

// The scalar render settings of a scene's "render" object (spp, seed, max_depth, threads,
// clamp, filter_glossy, and the choices model, integrator, ply_method). Their defaults are
// RenderSettings' (scene/scene.h; a test keeps the two equal).
const std::vector<ParamInfo>& render_settings();
const ParamInfo& render_setting(const std::string& name);  // throws std::out_of_range

std::vector<std::string> choice_names(const ChoiceList& list);
const Choice* find_choice(const ChoiceList& list, const std::string& name);  // nullptr when unknown
const char* choice_name(const ChoiceList& list, float value);  // the default's name when no choice has it
// "a, b or c": for messages and help text.
std::string choice_names_text(const ChoiceList& list);
// The value named `name`; throws InputError(source, place, "must be a, b or c, got \"name\"").
float parse_choice(const ChoiceList& list, const std::string& name, const std::string& source,
                   const std::string& place);

}  // namespace purl
