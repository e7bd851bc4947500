// Preset files: {"name", "description", "source", "material": {scene material object},
// "provenance": {...}}, the format the add-on's preset menu and the scene reader's
// "material": {"preset": ...} read (docs/fitting.md).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/fitter.h"
#include "scene/scene.h"

namespace purl {

// A bysdf material as the scene format writes it: every appearance parameter (ply colours
// only up to ply_color_count), the yarn geometry and the fiber BCSDF of the explicit reference.
nlohmann::json bysdf_material_json(const MaterialDesc& material);

struct FitSource {
    std::string scene, image, mask;  // as given on the command line
};

// The preset for a finished fit: `base` (the first target's first bysdf material) with the
// fitted parameters, plus where it came from and how well it fits.
nlohmann::json fit_preset_json(const std::string& name, const MaterialDesc& base, const FitResult& result,
                               const std::vector<FitSource>& sources, const FitOptions& options);

// Writes JSON to `path` through a temporary file; throws InputError naming the path.
void write_json_file(const std::string& path, const nlohmann::json& value);

}  // namespace purl
