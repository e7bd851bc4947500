// libFuzzer target: yarn preset files as the add-on reads them ({"name", "material": {...},
// ...}). The material object goes through the native reader the way a render would see it:
// wrapped in a fixed scene (camera + one tiny in-memory yarn) and parsed by parse_scene_text.
// An accepted material must then hold only in-range, finite parameters and a yarn
// description that check_yarn_description accepts.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "bsdf/params.h"
#include "scene/input_error.h"
#include "scene/scene_json.h"

namespace {

using namespace purl;
using nlohmann::json;

[[noreturn]] void broken(const std::string& what) {
    std::fprintf(stderr, "accepted material with %s\n", what.c_str());
    std::abort();
}

template <class Params>
void check_table(const Params& p, const std::vector<ParamInfo>& table, const char* group) {
    for (const ParamInfo& info : table)
        for (int c = 0; c < info.components; ++c) {
            const float v = param_field(p, info)[c];
            if (!(v >= info.min_value && v <= info.max_value))  // NaN fails too
                broken(std::string(group) + "." + info.name + " = " + std::to_string(v) + " out of its range");
        }
}

void check_material(const MaterialDesc& m) {
    if (m.model == "placeholder") {
        check_table(m.placeholder, placeholder_param_table(), "placeholder");
        return;
    }
    if (m.model != "bysdf") broken("unknown model " + m.model);
    check_table(m.bysdf, bysdf_param_table(), "bysdf");
    try {
        check_yarn_description(m.yarn, "fuzz", "yarn");
    } catch (const InputError& e) {
        broken(std::string("a yarn description check_yarn_description rejects: ") + e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static ExternalArrays arrays = [] {
        ExternalArrays a;
        a.yarns = [](const std::string&) {
            YarnCurves c;
            const Vec4 p[4] = {{0, 0, 0, 0.01f}, {0.1f, 0, 0, 0.01f}, {0.2f, 0, 0, 0.01f}, {0.3f, 0, 0, 0.01f}};
            c.add_curve(p, 4, false);
            return c;
        };
        return a;
    }();
    // The add-on's read_preset: a JSON object with a "material" object, or it is not a preset.
    const json preset = json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
    if (!preset.is_object() || !preset.contains("material") || !preset["material"].is_object()) return 0;

    const json scene = {
        {"camera", {{"position", {0, -1, 0}}, {"look_at", {0, 0, 0}}}},
        {"yarns", json::array({{{"arrays", "preset"}, {"material", preset["material"]}}})},
    };
    SceneDesc parsed;
    try {
        parsed = parse_scene_text(scene.dump(), "preset.json", "", &arrays);
    } catch (const InputError&) {
        return 0;  // a clear error; any other exception escapes and is a finding
    }
    check_material(parsed.yarns.at(0).material);
    return 0;
}
