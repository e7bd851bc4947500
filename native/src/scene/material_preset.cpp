#include "scene/material_preset.h"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/input_error.h"
#include "scene/json_reader.h"

#ifndef PURL_PRESET_DIR
#define PURL_PRESET_DIR ""
#endif

namespace purl {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr uintmax_t kMaxPresetBytes = uintmax_t(1) << 20;  // presets are a few kB

// Preset names are plain file names: no folders, so a scene cannot reach outside the preset dirs.
bool plain_name(const std::string& name) {
    if (name.empty() || name.size() > 100) return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
    return name.front() != '.';
}

json read_preset_json(const std::string& path, const std::string& file, const std::string& place) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(file, place, "preset file " + path + " does not exist");
    if (!fs::is_regular_file(path, ec)) throw InputError(path, "", "not a regular file");
    if (fs::file_size(path, ec) > kMaxPresetBytes) throw InputError(path, "", "too large for a preset (over 1 MiB)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file");
    std::stringstream text;
    text << in.rdbuf();
    const json preset = parse_json_text(text.str(), path);
    if (!preset.is_object() || !preset.contains("material") || !preset["material"].is_object())
        throw InputError(path, "", "a preset needs a \"material\" object");
    const json& material = preset["material"];
    if (material.contains("preset_file") || (material.contains("preset") && material_uses_preset(material)))
        throw InputError(path, "material", "a preset cannot name another preset");
    return material;
}

}  // namespace

bool material_uses_preset(const json& material) {
    if (!material.is_object()) return false;
    if (material.contains("preset_file")) return true;
    const bool fiber_model = material.contains("model") && material["model"] == "fiber";
    return material.contains("preset") && !fiber_model;
}

std::vector<std::string> material_preset_dirs() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("PURL_PRESET_PATH")) {
        std::stringstream list(env);
        std::string dir;
        while (std::getline(list, dir, ':'))
            if (!dir.empty()) dirs.push_back(dir);
    }
    if (std::string(PURL_PRESET_DIR).size()) dirs.push_back(PURL_PRESET_DIR);
    return dirs;
}

MaterialPreset load_material_preset(const json& material, const std::string& file, const std::string& place,
                                    const std::string& base_dir) {
    MaterialPreset out;
    if (!material_uses_preset(material)) return out;
    if (material.contains("preset") && material.contains("preset_file"))
        throw InputError(file, place, "give either preset or preset_file, not both");
    if (material.contains("preset_file")) {
        if (!material["preset_file"].is_string())
            throw InputError(file, place + ".preset_file", "must be a path (string)");
        const std::string given = material["preset_file"].get<std::string>();
        if (given.find('\0') != std::string::npos)
            throw InputError(file, place + ".preset_file", "contains a NUL character; a file name cannot");
        out.path = given.empty() || fs::path(given).is_absolute() || base_dir.empty()
                       ? given
                       : (fs::path(base_dir) / given).string();
        out.material = read_preset_json(out.path, file, place + ".preset_file");
        return out;
    }
    if (!material["preset"].is_string()) throw InputError(file, place + ".preset", "must be a preset name (string)");
    const std::string name = material["preset"].get<std::string>();
    if (!plain_name(name))
        throw InputError(file, place + ".preset",
                         "\"" + name + "\" is not a preset name (letters, digits, '_', '-'; use preset_file for a path)");
    std::string searched, known;
    for (const std::string& dir : material_preset_dirs()) {
        const fs::path candidate = fs::path(dir) / (name + ".json");
        std::error_code ec;
        if (fs::exists(candidate, ec)) {
            out.path = candidate.string();
            out.material = read_preset_json(out.path, file, place + ".preset");
            return out;
        }
        searched += (searched.empty() ? "" : ", ") + dir;
        for (const auto& entry : fs::directory_iterator(dir, ec))
            if (entry.path().extension() == ".json")
                known += (known.empty() ? "" : ", ") + entry.path().stem().string();
    }
    throw InputError(file, place + ".preset",
                     "no preset \"" + name + "\" in " + (searched.empty() ? "any folder" : searched) +
                         (known.empty() ? "" : " (known: " + known + ")"));
}

json merge_material(const json& preset_material, const json& overrides) {
    json merged = preset_material;
    for (auto it = overrides.begin(); it != overrides.end(); ++it) {
        if (it.key() == "preset" || it.key() == "preset_file") continue;
        if (it.value().is_object() && merged.contains(it.key()) && merged[it.key()].is_object())
            for (auto inner = it.value().begin(); inner != it.value().end(); ++inner)
                merged[it.key()][inner.key()] = inner.value();
        else
            merged[it.key()] = it.value();
    }
    return merged;
}

}  // namespace purl
