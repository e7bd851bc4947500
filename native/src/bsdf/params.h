// One declaration per material parameter: name, unit, range, default and meaning.
// The JSON reader, the Python module (purlcore.material_parameters()), the Blender UI and
// docs/parameters.md are all derived from these tables; nothing else lists parameters.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace purl {

struct ParamInfo {
    const char* name;   // JSON / Python key
    const char* unit;   // "" for dimensionless, e.g. "1/m", "rad", "m"
    int components;     // 1 for a scalar, 3 for a colour or vector
    float min_value, max_value;
    float default_value[3];
    const char* doc;    // one sentence, used as the UI tooltip
    size_t offset;      // byte offset of the float (or float[3]) inside the parameter struct
    bool is_color;      // shown as a colour picker
    bool is_integer = false;  // whole numbers only (counts, seeds): shown as an integer field
    bool is_sign = false;     // -1 or +1 only (twist directions): shown as a choice of two
    const char* label = nullptr;  // short name for the UI, unit not included (nullptr: from `name`)
};

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
