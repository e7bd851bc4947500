// Reads the JSON scene format of docs/scene-format.md into a SceneDesc.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace purl {

// Where yarns and meshes named by {"arrays": "name"} come from (the Python module).
struct ExternalArrays {
    std::function<YarnCurves(const std::string& name)> yarns;
    std::function<MeshDesc(const std::string& name)> meshes;
};

// Only the camera and film of a scene (everything else is left unread and unchecked).
SceneDesc parse_view_text(const std::string& text, const std::string& source);

// render.model and render.ply_method by name (base/registry.h); InputError for other names.
YarnModel parse_yarn_model(const std::string& name, const std::string& source);
PlyCrossSection parse_ply_method(const std::string& name, const std::string& source);

SceneDesc load_scene_file(const std::string& path);
// `source` names the scene in messages; relative paths resolve against `base_dir`.
SceneDesc parse_scene_text(const std::string& text, const std::string& source,
                           const std::string& base_dir, const ExternalArrays* arrays = nullptr);

}  // namespace purl
