// One declaration per parameter or setting: name, unit, kind, range, default and meaning.
// The JSON reader, the Python module (purlcore.material_parameters(), render_settings()), the
// CLI, the Blender UI and docs/parameters.md are all derived from these tables; nothing else
// lists parameters.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace purl {

// One value of a named choice (base/registry.h): its name in JSON and Python, what the UI shows,
// and the number it stands for where it is stored (an enum's value, or -1/+1 for a sign).
struct Choice {
    const char* name;
    const char* label;
    const char* doc;
    float value;
};

struct ChoiceList {
    const char* key;  // where it is read: "render.ply_method", "material.yarn.ply_handedness", ...
    std::vector<Choice> choices;
    const char* default_name;
};

// What a declared value holds. Material fields are floats in their struct whatever the kind
// (so one offset table serves them all); the kind says what values are valid and how the UI
// shows them.
enum class ParamKind {
    Float,    // any number in [min, max]
    Integer,  // whole numbers in [min, max] (counts, seeds): shown as an integer field
    Enum,     // one of `choices`, stored as the choice's value (twist directions: -1 or +1)
};

struct ParamInfo {
    const char* name;   // JSON / Python key
    const char* unit;   // "" for dimensionless, e.g. "1/m", "rad", "m"
    int components;     // 1 for a scalar, 3 for a colour or vector
    // Double, so that integer settings up to 2^31 - 1 (seeds) keep their exact bounds.
    double min_value, max_value;
    float default_value[3];
    const char* doc;    // one sentence, used as the UI tooltip
    size_t offset;      // byte offset of the float (or float[3]) inside the parameter struct
    bool is_color;      // shown as a colour picker
    ParamKind kind = ParamKind::Float;
    const ChoiceList* choices = nullptr;  // the values of an Enum
    const char* label = nullptr;  // short name for the UI, unit not included (nullptr: from `name`)

    bool is_integer() const { return kind == ParamKind::Integer; }
    // An Enum over -1 and +1 (twist directions), shown as a choice of two.
    bool is_sign() const;
};

inline bool ParamInfo::is_sign() const {
    if (kind != ParamKind::Enum || !choices || choices->choices.size() != 2) return false;
    return choices->choices[0].value == -1.0f && choices->choices[1].value == 1.0f;
}

// The same declaration with a UI label.
inline ParamInfo labelled(ParamInfo info, const char* label) {
    info.label = label;
    return info;
}

// Reads a float field described by `info` from a parameter struct.
template <class Params>
float* param_field(Params& p, const ParamInfo& info) {
    return reinterpret_cast<float*>(reinterpret_cast<char*>(&p) + info.offset);
}
template <class Params>
const float* param_field(const Params& p, const ParamInfo& info) {
    return reinterpret_cast<const float*>(reinterpret_cast<const char*>(&p) + info.offset);
}

// Fills every declared field of `p` with its default.
template <class Params>
void apply_defaults(Params& p, const std::vector<ParamInfo>& table) {
    for (const ParamInfo& info : table)
        for (int c = 0; c < info.components; ++c) param_field(p, info)[c] = info.default_value[c];
}

}  // namespace purl
