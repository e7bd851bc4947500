// Material presets in scenes: "material": {"preset": "cotton", ...overrides} or
// {"preset_file": "my_yarn.json", ...}. A preset file is {"material": {...}, ...} (the
// add-on's and `purl fit`'s format, docs/fitting.md); named presets are looked up as
// <dir>/<name>.json in $PURL_PRESET_PATH (folders separated by ':') and then this checkout's
// presets/ folder. With model "fiber", "preset" keeps naming a fiber BCSDF fit instead.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace purl {

struct MaterialPreset {
    std::string path;          // the preset file read ("" when the material names no preset)
    nlohmann::json material;   // its material object
};

// True when `material` (a scene material object) asks for a preset file.
bool material_uses_preset(const nlohmann::json& material);

// Finds and reads the preset `material` names. `file`/`place` name the scene and the material
// in errors; `base_dir` resolves preset_file. Throws InputError.
MaterialPreset load_material_preset(const nlohmann::json& material, const std::string& file, const std::string& place,
                                    const std::string& base_dir);

// The preset's material with the scene's keys on top ("preset"/"preset_file" dropped); nested
// objects ("yarn", "fiber") merge key by key.
nlohmann::json merge_material(const nlohmann::json& preset_material, const nlohmann::json& overrides);

// Folders searched for named presets, in order.
std::vector<std::string> material_preset_dirs();

}  // namespace purl
