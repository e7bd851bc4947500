// What each fuzz target runs on one input, shared with the regression tests
// (tests/native/robustness/test_fuzz_regressions.cpp) so a saved finding replays exactly.
// Each check returns "" when the input ended well: a clear InputError (its text goes to
// *error) or a result the renderer can take as it is. Otherwise it returns what went wrong.
// Any other exception escapes: for libFuzzer that is a finding too.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/input_error.h"
#include "base/param_info.h"
#include "scene/bcc.h"
#include "scene/curves.h"
#include "scene/scene_json.h"

namespace purl::fuzz {

// ---- BCC: read_bcc and load_bcc through an in-memory file, so the real path-based entry
// point runs, size checks and all, without touching the disk.

// One in-memory file per name (fuzz.bcc, fuzz-preset.json), rewritten for every input.
inline std::string memory_file_path(const char* name, const uint8_t* data, size_t size) {
    static std::map<std::string, int> fds;
    auto found = fds.find(name);
    if (found == fds.end()) found = fds.emplace(name, memfd_create(name, 0)).first;
    const int fd = found->second;
    if (fd < 0 || ftruncate(fd, 0) != 0) std::abort();
    for (size_t done = 0; done < size;) {
        const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) std::abort();
        done += static_cast<size_t>(n);
    }
    // Opening /proc/self/fd/N gives a fresh file position, like opening a real file.
    return "/proc/self/fd/" + std::to_string(fd);
}

inline std::string check_bcc(const uint8_t* data, size_t size, std::string* error = nullptr) {
    const std::string path = memory_file_path("fuzz.bcc", data, size);
    YarnCurves curves;
    try {
        curves = load_bcc(path, 0.01f);
    } catch (const InputError& e) {
        if (error) *error = e.what();
        return "";
    }
    // What load_bcc accepts must be renderable: a rejection here is a reader bug, except for
    // the radius rule, which depends on the radius the scene gives, not on the file.
    try {
        validate_curves(curves, path);
    } catch (const InputError& e) {
        if (e.reason().find("is larger than the whole yarn set") != std::string::npos) return "";
        return std::string("load_bcc accepted curves that validate_curves rejects: ") + e.what();
    }
    return "";
}

// ---- JSON scenes: parse_scene_text, then the invariants the renderer relies on, so a value
// that slipped through (an infinite vertex, an index out of range) is a finding too.

inline bool finite(const Transform& t) {
    for (const auto& row : t.m)
        for (float v : row)
            if (!std::isfinite(v)) return false;
    return true;
}

// In-memory arrays for {"arrays": name}, as the Python module would give them.
inline const ExternalArrays& fixed_arrays() {
    static const ExternalArrays arrays = [] {
        ExternalArrays a;
        a.yarns = [](const std::string&) {
            YarnCurves c;
            const Vec4 p[5] = {{0, 0, 0, 0.01f}, {0.1f, 0, 0, 0.01f}, {0.2f, 0.05f, 0, 0.01f},
                               {0.3f, 0, 0, 0.01f}, {0.4f, 0, 0, 0.01f}};
            c.add_curve(p, 5, false);
            return c;
        };
        a.meshes = [](const std::string&) {
            MeshDesc m;
            m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
            m.indices = {0, 1, 2};
            return m;
        };
        return a;
    }();
    return arrays;
}

inline std::string check_scene_desc(const SceneDesc& s) {
    if (!finite(s.camera.to_world)) return "a non-finite camera placement";
    if (s.film.width < 1 || s.film.height < 1) return "an empty film";
    if (s.render.spp < 1 || s.render.max_depth < 1) return "no samples or no bounces";
    for (const LightDesc& l : s.lights) {
        if (!finite(l.to_world)) return "a non-finite light placement";
        if (!is_finite(l.color) || !std::isfinite(l.power) || !std::isfinite(l.strength)) return "a non-finite light";
    }
    for (const YarnSetDesc& y : s.yarns) {
        try {
            validate_curves(y.curves, "yarns");
        } catch (const InputError& e) {
            return std::string("yarn curves that validate_curves rejects: ") + e.what();
        }
    }
    for (const MeshDesc& m : s.meshes) {
        if (m.indices.size() % 3 != 0) return "a partial triangle";
        for (uint32_t i : m.indices)
            if (i >= m.vertices.size()) return "a triangle index out of range";
        for (const Vec3& v : m.vertices)
            if (!is_finite(v)) return "a non-finite mesh vertex";
    }
    return "";
}

inline std::string check_scene_json(const std::string& text, const std::string& data_dir,
                                    std::string* error = nullptr) {
    SceneDesc scene;
    try {
        scene = parse_scene_text(text, "fuzz.json", data_dir, &fixed_arrays());
    } catch (const InputError& e) {
        if (error) *error = e.what();
        return "";
    }
    const std::string broken = check_scene_desc(scene);
    return broken.empty() ? "" : "parse_scene_text accepted a scene with " + broken;
}

// ---- Preset files ({"material": {...}, ...}, the add-on's and `purl fit`'s format): read the
// way a scene reads them, through "material": {"preset_file": ...} (scene/material_preset.h),
// in a fixed scene (camera + one tiny in-memory yarn). An accepted material must hold only
// in-range parameters and a valid yarn description.

template <class Params>
std::string check_table(const Params& p, const std::vector<ParamInfo>& table, const char* group) {
    for (const ParamInfo& info : table)
        for (int c = 0; c < info.components; ++c) {
            const float v = param_field(p, info)[c];
            if (!(v >= info.min_value && v <= info.max_value))  // NaN fails too
                return std::string(group) + "." + info.name + " = " + std::to_string(v) + " out of its range";
        }
    return "";
}

inline std::string check_material(const MaterialDesc& m) {
    if (m.model == MaterialModel::Placeholder) return check_table(m.placeholder, placeholder_param_table(), "placeholder");
    if (m.model != MaterialModel::Bysdf) return std::string("unknown model ") + material_model_name(m.model);
    const std::string bad = check_table(m.bysdf, bysdf_param_table(), "bysdf");
    if (!bad.empty()) return bad;
    try {
        check_yarn_description(m.yarn, "preset", "yarn");
    } catch (const InputError& e) {
        return std::string("a yarn description check_yarn_description rejects: ") + e.what();
    }
    return "";
}

inline std::string check_preset(const uint8_t* data, size_t size, std::string* error = nullptr) {
    using nlohmann::json;
    const std::string preset_path = memory_file_path("fuzz-preset.json", data, size);
    const json scene = {
        {"camera", {{"position", {0, -1, 0}}, {"look_at", {0, 0, 0}}}},
        {"yarns", json::array({{{"arrays", "preset"}, {"material", {{"preset_file", preset_path}}}}})},
    };
    SceneDesc parsed;
    try {
        parsed = parse_scene_text(scene.dump(), "scene.json", "", &fixed_arrays());
    } catch (const InputError& e) {
        if (error) *error = e.what();
        return "";
    }
    const std::string broken = check_material(parsed.yarns.at(0).material);
    return broken.empty() ? "" : "accepted a material with " + broken;
}

}  // namespace purl::fuzz
