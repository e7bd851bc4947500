// libFuzzer target: the JSON scene reader (parse_scene_text). Every input must either give
// an InputError or a scene the renderer can take as it is; the checks after a successful
// parse turn a value that slipped through (an infinite vertex, an out-of-range index) into
// a finding instead of a silent acceptance.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scene/curves.h"
#include "scene/input_error.h"
#include "scene/scene_json.h"

#ifndef PURL_FUZZ_DATA_DIR
#error "PURL_FUZZ_DATA_DIR must name tests/fuzz/data (small BCC and OBJ files scenes may refer to)"
#endif

namespace {

using namespace purl;

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "parse_scene_text accepted a scene with %s\n", what);
    std::abort();
}

bool finite(const Transform& t) {
    for (const auto& row : t.m)
        for (float v : row)
            if (!std::isfinite(v)) return false;
    return true;
}

// In-memory arrays for {"arrays": name}, as the Python module would give them.
ExternalArrays fixed_arrays() {
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
}

void check_scene(const SceneDesc& s) {
    if (!finite(s.camera.to_world)) broken("a non-finite camera placement");
    if (s.film.width < 1 || s.film.height < 1) broken("an empty film");
    if (s.render.spp < 1 || s.render.max_depth < 1) broken("no samples or no bounces");
    for (const LightDesc& l : s.lights) {
        if (!finite(l.to_world)) broken("a non-finite light placement");
        if (!is_finite(l.color) || !std::isfinite(l.power) || !std::isfinite(l.strength))
            broken("a non-finite light");
    }
    for (const YarnSetDesc& y : s.yarns) {
        try {
            validate_curves(y.curves, "fuzz");
        } catch (const InputError& e) {
            std::fprintf(stderr, "%s\n", e.what());
            broken("yarn curves that validate_curves rejects");
        }
    }
    for (const MeshDesc& m : s.meshes) {
        if (m.indices.size() % 3 != 0) broken("a partial triangle");
        for (uint32_t i : m.indices)
            if (i >= m.vertices.size()) broken("a triangle index out of range");
        for (const Vec3& v : m.vertices)
            if (!is_finite(v)) broken("a non-finite mesh vertex");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const ExternalArrays arrays = fixed_arrays();
    const std::string text(reinterpret_cast<const char*>(data), size);
    SceneDesc scene;
    try {
        scene = parse_scene_text(text, "fuzz.json", PURL_FUZZ_DATA_DIR, &arrays);
    } catch (const InputError&) {
        return 0;  // a clear error; any other exception escapes and is a finding
    }
    check_scene(scene);
    return 0;
}
