#include "scene/json_reader.h"

#include <cmath>

namespace purl {

using nlohmann::json;

namespace {
const char* type_name(const json& v) {
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}
}  // namespace

JsonObject::JsonObject(const json& value, std::string path, std::string file)
    : value_(value), path_(std::move(path)), file_(std::move(file)) {
    if (!value_.is_object())
        throw InputError(file_, path_.empty() ? "top level" : path_,
                         std::string("must be an object, got ") + type_name(value_));
}

std::string JsonObject::child_path(const char* key) const {
    return path_.empty() ? std::string(key) : path_ + "." + key;
}

void JsonObject::fail(const char* key, const std::string& reason) const {
    throw InputError(file_, key ? child_path(key) : path_, reason);
}

const json& JsonObject::take(const char* key) {
    read_.insert(key);
    return value_.at(key);
}

const json& JsonObject::raw(const char* key) {
    if (!has(key)) fail(key, "is required");
    return take(key);
}

float JsonObject::number(const char* key, float fallback, float lo, float hi) {
    if (!has(key)) return fallback;
    const json& v = take(key);
    if (!v.is_number()) fail(key, std::string("must be a number, got ") + type_name(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi)
        fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                      std::to_string(d));
    return static_cast<float>(d);
}

float JsonObject::required_number(const char* key, float lo, float hi) {
    if (!has(key)) fail(key, "is required");
    return number(key, 0.0f, lo, hi);
}

int JsonObject::integer(const char* key, int fallback, int lo, int hi) {
    if (!has(key)) return fallback;
    const json& v = take(key);
    if (!v.is_number_integer()) fail(key, std::string("must be an integer, got ") + type_name(v));
    const long long i = v.get<long long>();
    if (i < lo || i > hi)
        fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                      std::to_string(i));
    return static_cast<int>(i);
}

bool JsonObject::boolean(const char* key, bool fallback) {
    if (!has(key)) return fallback;
    const json& v = take(key);
    if (!v.is_boolean()) fail(key, std::string("must be true or false, got ") + type_name(v));
    return v.get<bool>();
}

std::string JsonObject::string(const char* key, const std::string& fallback) {
    if (!has(key)) return fallback;
    const json& v = take(key);
    if (!v.is_string()) fail(key, std::string("must be a string, got ") + type_name(v));
    return v.get<std::string>();
}

std::string JsonObject::choice(const char* key, const std::string& fallback,
                               const std::vector<std::string>& choices) {
    const std::string s = string(key, fallback);
    for (const std::string& c : choices) {
        std::string upper_s = s, upper_c = c;
        for (char& ch : upper_s) ch = static_cast<char>(std::toupper(ch));
        for (char& ch : upper_c) ch = static_cast<char>(std::toupper(ch));
        if (upper_s == upper_c) return c;
    }
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    fail(key, "must be one of " + list + ", got \"" + s + "\"");
}

void JsonObject::floats(const char* key, float* out, int count) {
    const json& v = raw(key);
    if (!v.is_array() || static_cast<int>(v.size()) != count)
        fail(key, "must be an array of " + std::to_string(count) + " numbers");
    for (int i = 0; i < count; ++i) {
        if (!v[i].is_number()) fail(key, "element " + std::to_string(i) + " is not a number");
        out[i] = v[i].get<float>();
        if (!std::isfinite(out[i])) fail(key, "element " + std::to_string(i) + " is not finite");
    }
}

Vec3 JsonObject::vec3(const char* key, Vec3 fallback) {
    if (!has(key)) return fallback;
    float f[3];
    floats(key, f, 3);
    return {f[0], f[1], f[2]};
}

Transform JsonObject::transform(const char* key) {
    float f[16];
    floats(key, f, 16);
    Transform t;
    for (int i = 0; i < 16; ++i) t.m[i / 4][i % 4] = f[i];
    if (f[12] != 0 || f[13] != 0 || f[14] != 0 || f[15] != 1)
        fail(key, "last row must be 0 0 0 1 (an affine transform)");
    if (!(t.uniform_scale() > 0)) fail(key, "is singular");
    return t;
}

Transform JsonObject::placement() {
    if (has("matrix_world")) {
        if (has("position") || has("look_at"))
            fail("matrix_world", "give either matrix_world or position + look_at, not both");
        return transform("matrix_world");
    }
    if (!has("position")) fail(nullptr, "needs matrix_world or position + look_at");
    const Vec3 position = vec3("position", Vec3(0.0f));
    if (!has("look_at")) fail("look_at", "is required with position");
    const Vec3 target = vec3("look_at", Vec3(0.0f));
    const Vec3 up = vec3("up", Vec3(0, 0, 1));
    if (length(position - target) < 1e-9f) fail("look_at", "equals position");
    return Transform::look_at(position, target, up);
}

JsonObject JsonObject::object(const char* key) { return JsonObject(raw(key), child_path(key), file_); }

std::vector<JsonObject> JsonObject::array_of_objects(const char* key) {
    std::vector<JsonObject> out;
    if (!has(key)) return out;
    const json& v = take(key);
    if (!v.is_array()) fail(key, std::string("must be an array, got ") + type_name(v));
    for (size_t i = 0; i < v.size(); ++i)
        out.emplace_back(v[i], child_path(key) + "[" + std::to_string(i) + "]", file_);
    return out;
}

void JsonObject::finish() const {
    for (auto it = value_.begin(); it != value_.end(); ++it)
        if (!read_.count(it.key())) fail(it.key().c_str(), "unknown key");
}

}  // namespace purl
