#include "scene/scene_files.h"

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "base/input_error.h"
#include "scene/scene_json.h"

namespace purl {

namespace fs = std::filesystem;

namespace {

bool is_inside(const fs::path& folder, const fs::path& path) {
    std::error_code ec;
    const fs::path relative = fs::weakly_canonical(path, ec).lexically_relative(fs::weakly_canonical(folder, ec));
    return !ec && !relative.empty() && *relative.begin() != "..";
}

SceneFileStatus status_of(const SceneFile& file, const fs::path& folder) {
    SceneFileStatus s;
    s.file = file;
    std::error_code ec;
    s.exists = fs::is_regular_file(file.path, ec);
    s.bytes = s.exists ? fs::file_size(file.path, ec) : 0;
    s.inside_scene_folder = is_inside(folder, file.path);
    return s;
}

fs::path scene_folder(const std::string& scene_path) {
    const fs::path parent = fs::path(scene_path).parent_path();
    return parent.empty() ? fs::path(".") : parent;
}

std::string size_text(uintmax_t bytes) {
    char text[32];
    const double b = double(bytes);
    if (b < 1e3) std::snprintf(text, sizeof text, "%.0f B", b);
    else if (b < 1e6) std::snprintf(text, sizeof text, "%.1f kB", b / 1e3);
    else if (b < 1e9) std::snprintf(text, sizeof text, "%.1f MB", b / 1e6);
    else std::snprintf(text, sizeof text, "%.2f GB", b / 1e9);
    return text;
}

std::string padded(std::string text, size_t width) {
    if (text.size() < width) text.append(width - text.size(), ' ');
    return text;
}

}  // namespace

std::vector<SceneFileStatus> scene_file_statuses(const std::string& scene_path) {
    const SceneDesc scene = load_scene_file(scene_path);
    const fs::path folder = scene_folder(scene_path);
    std::vector<SceneFileStatus> out{status_of({"scene", "", scene_path}, folder)};
    for (const SceneFile& file : scene.files) out.push_back(status_of(file, folder));
    return out;
}

std::string scene_files_table(const std::string& scene_path, const std::vector<SceneFileStatus>& files) {
    const fs::path folder = scene_folder(scene_path);
    size_t place_width = 5, outside = 0, missing = 0;
    uintmax_t total = 0;
    for (const SceneFileStatus& s : files) {
        place_width = std::max(place_width, s.file.place.size());
        outside += !s.inside_scene_folder;
        missing += !s.exists;
        total += s.bytes;
    }
    std::string text = scene_path + ": " + std::to_string(files.size()) + " files, " + size_text(total) + "; " +
                       std::to_string(outside) + " outside the scene's folder, " + std::to_string(missing) +
                       " missing\n";
    text += padded("role", 13) + padded("place", place_width + 2) + padded("size", 10) + "path\n";
    for (const SceneFileStatus& s : files) {
        const std::string shown = s.inside_scene_folder
                                      ? fs::path(s.file.path).lexically_proximate(folder).string()
                                      : fs::absolute(s.file.path).lexically_normal().string();
        const char* note = s.inside_scene_folder      ? ""
                           : s.file.role == "preset" ? "   (named preset: workers find it on their preset path)"
                                                     : "   (outside the scene's folder: needed at this path)";
        text += padded(s.file.role, 13) + padded(s.file.place.empty() ? "-" : s.file.place, place_width + 2) +
                padded(s.exists ? size_text(s.bytes) : "missing", 10) + shown + note + "\n";
    }
    return text;
}

std::string scene_files_json(const std::string& scene_path, const std::vector<SceneFileStatus>& files) {
    nlohmann::json list = nlohmann::json::array();
    for (const SceneFileStatus& s : files)
        list.push_back({{"role", s.file.role},
                        {"place", s.file.place},
                        {"path", fs::absolute(s.file.path).lexically_normal().string()},
                        {"exists", s.exists},
                        {"bytes", s.bytes},
                        {"inside_scene_folder", s.inside_scene_folder}});
    const nlohmann::json root = {{"scene", fs::absolute(scene_path).lexically_normal().string()}, {"files", list}};
    return root.dump(2) + "\n";
}

int run_deps_command(const std::string& scene_path, bool json, std::FILE* out) {
    const std::vector<SceneFileStatus> files = scene_file_statuses(scene_path);
    const std::string text = json ? scene_files_json(scene_path, files) : scene_files_table(scene_path, files);
    std::fputs(text.c_str(), out);
    std::fflush(out);
    for (const SceneFileStatus& s : files)
        if (!s.exists) throw InputError(scene_path, s.file.place, "file " + s.file.path + " does not exist");
    return 0;
}

}  // namespace purl
