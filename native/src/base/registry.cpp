#include "base/registry.h"

#include <stdexcept>

#include "base/input_error.h"

namespace purl {

const ChoiceList& yarn_models() {
    // Values are YarnModel's (scene/scene.h), in this order.
    static const ChoiceList list{
        "render.model",
        {{"bysdf", "BYSDF", "Implicit plies and fibers: the BYSDF (the renderer's model)", 0},
         {"ply", "Explicit Plies", "Explicit ply curves made from the yarns (reference)", 1},
         {"fiber", "Explicit Fibers", "Explicit fiber curves made from the yarns (ground truth)", 2}},
        "bysdf"};
    return list;
}

const ChoiceList& material_models() {
    // Values are MaterialModel's (scene/scene.h), in this order; its fourth, Ply, is made only
    // by the explicit reference, never read.
    static const ChoiceList list{
        "material.model",
        {{"bysdf", "Yarn (plies and fibers)", "The BYSDF over implicit plies and fibers", 0},
         {"placeholder", "Simple (diffuse + gloss)", "A diffuse and a glossy lobe, no yarn structure", 1},
         {"fiber", "Single fibers", "The fiber BCSDF, for curves that already are fibers", 2}},
        "bysdf"};
    return list;
}

const ChoiceList& ply_methods() {
    static const ChoiceList list{
        "render.ply_method",
        {{"elliptical", "Elliptical",
          "Exact ply search along the ray (the default; bounce rays whose cone spans a ply use the circular cut)",
          float(PlyCrossSection::elliptical)},
         {"local", "Local",
          "The yarn straightened at each hit: about a fifth faster, exact on straight yarns, drifts on tight bends",
          float(PlyCrossSection::local)},
         {"circular", "Circular", "The older perpendicular cross-section: fastest, for comparison only",
          float(PlyCrossSection::circular)}},
        "elliptical"};
    return list;
}

const ChoiceList& multiscale_modes() {
    // Values are MultiscaleMode's (scene/multiscale_settings.h), in this order.
    static const ChoiceList list{
        "render.multiscale.mode",
        {{"near", "Near", "Always shade plies and fibers individually", 0},
         {"multi", "Multi", "Average the yarn over the part a pixel covers (near where it covers one fiber)", 1},
         {"far", "Far", "Average the whole yarn width (for yarns thinner than a pixel)", 2},
         {"auto", "Auto", "Pick near, multi or far scale from the yarn's pixel coverage", 3}},
        "auto"};
    return list;
}

const ChoiceList& multiscale_aggregations() {
    // Values are MultiscaleAggregation's (scene/multiscale_settings.h).
    static const ChoiceList list{
        "render.multiscale.aggregation",
        {{"mixture", "Mixture", "Pick one h sample per light sample, weighted by its share", 0},
         {"aggregate", "Aggregate", "Evaluate every h sample and average them", 1}},
        "mixture"};
    return list;
}

const ChoiceList& integrators() {
    static const ChoiceList list{
        "render.integrator",
        {{"path", "Path Tracing", "Path tracing with next-event estimation (the renderer)", 0},
         {"trace", "Trace Only",
          "Camera rays only, every first hit a constant grey: traversal alone (benchmark baseline)", 1}},
        "path"};
    return list;
}

const ChoiceList& twist_directions() {
    static const ChoiceList list{
        "handedness",
        {{"S", "Left (S)", "S twist: turns like the middle of the letter S (left-handed), stored as -1", -1.0f},
         {"Z", "Right (Z)", "Z twist: turns like the middle of the letter Z (right-handed), stored as +1", 1.0f}},
        "Z"};
    return list;
}

std::vector<const ChoiceList*> all_choice_lists() {
    return {&yarn_models(),      &material_models(), &ply_methods(),     &multiscale_modes(),
            &multiscale_aggregations(), &integrators(), &twist_directions()};
}

namespace {

// Render settings are not addressed by offset (RenderSettings holds ints, a seed and enums):
// the reader assigns each field by name.
ParamInfo setting(const char* label, const char* name, const char* unit, ParamKind kind, double lo, double hi,
                  float def, const char* doc, const ChoiceList* choices = nullptr) {
    ParamInfo info{name, unit, 1, lo, hi, {def, 0, 0}, doc, 0, false};
    info.kind = kind;
    info.choices = choices;
    info.label = label;
    return info;
}

ParamInfo choice_setting(const char* label, const char* name, const ChoiceList& list, const char* doc) {
    const float def = find_choice(list, list.default_name)->value;
    return setting(label, name, "", ParamKind::Enum, 0, double(list.choices.size() - 1), def, doc, &list);
}

std::vector<ParamInfo> build_render_settings() {
    constexpr double kHuge = 1e30;
    return {
        setting("Samples", "spp", "", ParamKind::Integer, 1, 1 << 20, 64, "Samples per pixel."),
        setting("Seed", "seed", "", ParamKind::Integer, 0, 2147483647, 0,
                "Random seed: the image is a function of scene, seed and samples."),
        setting("Max Bounces", "max_depth", "", ParamKind::Integer, 1, 1024, 8, "Path length limit."),
        setting("Threads", "threads", "", ParamKind::Integer, 0, 4096, 0, "Worker threads (0: all cores)."),
        setting("Clamp", "clamp", "", ParamKind::Float, 0, kHuge, 0,
                "Clamp sample radiance to this (0 turns clamping off)."),
        setting("Filter Glossy", "filter_glossy", "", ParamKind::Float, 0, 10, 1,
                "As in Cycles: after a diffuse-like bounce, glossy lobes are blurred by this much, which removes "
                "most fireflies at a small bias in indirect highlights (0: off)."),
        choice_setting("Model", "model", yarn_models(),
                       "Yarn model: bysdf (implicit plies) or the explicit references ply and fiber."),
        choice_setting("Integrator", "integrator", integrators(),
                       "path, or trace: camera rays only, constant shading (benchmark baseline)."),
        choice_setting("Ply Search", "ply_method", ply_methods(),
                       "How BYSDF yarns find the ply under a hit (docs/implicit-geometry.md)."),
    };
}

}  // namespace

const std::vector<ParamInfo>& render_settings() {
    static const std::vector<ParamInfo> table = build_render_settings();
    return table;
}

const ParamInfo& render_setting(const std::string& name) {
    for (const ParamInfo& info : render_settings())
        if (name == info.name) return info;
    throw std::out_of_range("no render setting \"" + name + "\"");
}

std::vector<std::string> choice_names(const ChoiceList& list) {
    std::vector<std::string> names;
    for (const Choice& c : list.choices) names.push_back(c.name);
    return names;
}

const Choice* find_choice(const ChoiceList& list, const std::string& name) {
    for (const Choice& c : list.choices)
        if (name == c.name) return &c;
    return nullptr;
}

const char* choice_name(const ChoiceList& list, float value) {
    for (const Choice& c : list.choices)
        if (c.value == value) return c.name;
    return list.default_name;
}

std::string choice_names_text(const ChoiceList& list) {
    std::string text;
    const size_t n = list.choices.size();
    for (size_t i = 0; i < n; ++i) {
        if (i > 0) text += i + 1 == n ? " or " : ", ";
        text += list.choices[i].name;
    }
    return text;
}

float parse_choice(const ChoiceList& list, const std::string& name, const std::string& source,
                   const std::string& place) {
    if (const Choice* c = find_choice(list, name)) return c->value;
    throw InputError(source, place, "must be " + choice_names_text(list) + ", got \"" + name + "\"");
}

}  // namespace purl
