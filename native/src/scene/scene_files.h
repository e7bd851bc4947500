// What rendering a scene file reads besides the scene file itself (`purl deps`): the list a
// render farm needs to ship with the scene, checked before any long work starts.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace purl {

struct SceneFileStatus {
    SceneFile file;
    bool exists = false;
    uintmax_t bytes = 0;
    // At or below the scene file's folder, so it travels with the folder; a file outside it
    // must be at the same absolute path on every worker.
    bool inside_scene_folder = false;
};

// The scene file itself (role "scene") and then every file it names, in the order it names them.
// Loads the scene as a render would (so a scene that would not render throws InputError here).
std::vector<SceneFileStatus> scene_file_statuses(const std::string& scene_path);

// A table for people, or a JSON object {"scene", "files": [{role, place, path, exists, bytes,
// inside_scene_folder}]} for tools; paths are absolute in JSON, relative to the scene's folder in the
// table where they lie inside it.
std::string scene_files_table(const std::string& scene_path, const std::vector<SceneFileStatus>& files);
std::string scene_files_json(const std::string& scene_path, const std::vector<SceneFileStatus>& files);

// `purl deps`: prints the table or JSON to `out`; throws InputError naming the first missing file
// (after printing, so the list is complete).
int run_deps_command(const std::string& scene_path, bool json, std::FILE* out);

}  // namespace purl
