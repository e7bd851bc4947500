// Strict reading of one JSON object: typed getters with ranges, and an error for every
// key nobody asked for, so a typo in a scene never silently drops a setting.
#pragma once
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "math/transform.h"
#include "scene/input_error.h"

namespace purl {

class JsonObject {
public:
    JsonObject(const nlohmann::json& value, std::string path, std::string file);

    bool has(const char* key) const { return value_.contains(key); }
    const std::string& path() const { return path_; }
    const std::string& file() const { return file_; }
    std::string child_path(const char* key) const;

    float number(const char* key, float fallback, float lo, float hi);
    float required_number(const char* key, float lo, float hi);
    int integer(const char* key, int fallback, int lo, int hi);
    bool boolean(const char* key, bool fallback);
    std::string string(const char* key, const std::string& fallback);
    // One of `choices`; upper/lower case is accepted as given in the list.
    std::string choice(const char* key, const std::string& fallback, const std::vector<std::string>& choices);
    Vec3 vec3(const char* key, Vec3 fallback);
    void floats(const char* key, float* out, int count);  // exactly `count` numbers
    Transform transform(const char* key);                  // 16 numbers, row-major
    // The placement of an object: matrix_world, or position + look_at (+ up). Required.
    Transform placement();
    // A nested value, marked as read; the caller checks its type.
    const nlohmann::json& raw(const char* key);
    JsonObject object(const char* key);
    std::vector<JsonObject> array_of_objects(const char* key);

    [[noreturn]] void fail(const char* key, const std::string& reason) const;
    // Throws for any key that was never read.
    void finish() const;

private:
    const nlohmann::json& take(const char* key);
    const nlohmann::json& value_;
    std::string path_, file_;
    std::set<std::string> read_;
};

}  // namespace purl
