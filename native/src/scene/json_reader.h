// Strict reading of one JSON object: typed getters with ranges, and an error for every
// key nobody asked for, so a typo in a scene never silently drops a setting.
#pragma once
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/input_error.h"
#include "math/number_text.h"
#include "math/transform.h"

namespace purl {

// Parses JSON text: an InputError naming `source` and the line and column for invalid JSON,
// and for a key given twice in one object (nlohmann would keep the last silently).
nlohmann::json parse_json_text(const std::string& text, const std::string& source);

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
    // Three numbers, each in [lo, hi] (colours: [0, 1]).
    Vec3 vec3_in(const char* key, Vec3 fallback, float lo, float hi);
    // A file name: a string without NUL characters (the system would cut the name there and
    // open another file).
    std::string path_string(const char* key);
    void floats(const char* key, float* out, int count);     // exactly `count` finite numbers
    void doubles(const char* key, double* out, int count);  // the same, unrounded
    Point64 point(const char* key, Point64 fallback);       // a position: 3 numbers, kept in double
    Transform64 transform(const char* key);                  // 16 numbers, row-major
    // The placement of an object: matrix_world, or position + look_at (+ up). Required.
    Transform64 placement();
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
