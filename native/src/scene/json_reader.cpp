#include "scene/json_reader.h"

#include <cmath>
#include <set>
#include <vector>

namespace purl {

using nlohmann::json;

namespace {

// nlohmann counts bytes from 1; report the line and column a person can find.
std::string place_of(const std::string& text, size_t byte) {
    const size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
    size_t line = 1, column = 1;
    for (size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Where the parser is, as a scene path ("yarns[1].material"), and the keys each open object
// has had so far.
struct OpenValue {
    bool array = false;
    int index = -1;
    std::string key;
    std::set<std::string> keys;
};

std::string path_of(const std::vector<OpenValue>& stack) {
    std::string path;
    for (size_t i = 0; i + 1 < stack.size(); ++i) {
        const OpenValue& v = stack[i];
        if (v.array) path += "[" + std::to_string(v.index) + "]";
        else path += (path.empty() ? "" : ".") + v.key;
    }
    return path;
}

const char* type_name(const json& v) {
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}
}  // namespace

json parse_json_text(const std::string& text, const std::string& source) {
    std::vector<OpenValue> stack;
    const auto element = [&] {  // a value starts inside an array: the next index
        if (!stack.empty() && stack.back().array) ++stack.back().index;
    };
    const json::parser_callback_t check = [&](int, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
            case json::parse_event_t::array_start:
                element();
                stack.push_back({event == json::parse_event_t::array_start, -1, "", {}});
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                if (!stack.empty()) stack.pop_back();
                break;
            case json::parse_event_t::key: {
                OpenValue& object = stack.back();
                object.key = parsed.get<std::string>();
                if (!object.keys.insert(object.key).second) {
                    std::vector<OpenValue> at = stack;
                    at.push_back({});
                    throw InputError(source, path_of(at), "given twice in the same object (JSON keeps only one)");
                }
                break;
            }
            case json::parse_event_t::value:
                element();
                break;
        }
        return true;
    };
    try {
        return json::parse(text, check);
    } catch (const json::parse_error& e) {
        const std::string what = e.what();
        const size_t detail = what.find("syntax error");
        throw InputError(source, place_of(text, e.byte),
                         "not valid JSON" + (detail == std::string::npos ? "" : " (" + what.substr(detail) + ")"));
    } catch (const json::exception& e) {
        // A number beyond the double range ("1e400") is out_of_range 406, which carries no
        // byte position; its message quotes the number, so the place is where that first occurs.
        const std::string what = e.what();
        const size_t open = what.find('\''), close = what.rfind('\'');
        const size_t at = open < close ? text.find(what.substr(open + 1, close - open - 1)) : std::string::npos;
        const size_t detail = what.find("] ");
        throw InputError(source, at == std::string::npos ? "" : place_of(text, at + 1),
                         "not valid JSON (" + (detail == std::string::npos ? what : what.substr(detail + 2)) + ")");
    }
}

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
        fail(key, "must be in [" + number_text(lo) + ", " + number_text(hi) + "], got " + v.dump());
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
    if (i < lo || i > hi) fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v.dump());
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

void JsonObject::doubles(const char* key, double* out, int count) {
    const json& v = raw(key);
    if (!v.is_array() || static_cast<int>(v.size()) != count)
        fail(key, "must be an array of " + std::to_string(count) + " numbers");
    for (int i = 0; i < count; ++i) {
        if (!v[i].is_number()) fail(key, "element " + std::to_string(i) + " is not a number");
        out[i] = v[i].get<double>();
    }
}

void JsonObject::floats(const char* key, float* out, int count) {
    std::vector<double> d(static_cast<size_t>(count));
    doubles(key, d.data(), count);
    for (int i = 0; i < count; ++i) {
        out[i] = static_cast<float>(d[size_t(i)]);
        if (!std::isfinite(out[i])) fail(key, "element " + std::to_string(i) + " is not finite");
    }
}

Vec3 JsonObject::vec3(const char* key, Vec3 fallback) {
    if (!has(key)) return fallback;
    float f[3];
    floats(key, f, 3);
    return {f[0], f[1], f[2]};
}

Vec3 JsonObject::vec3_in(const char* key, Vec3 fallback, float lo, float hi) {
    const Vec3 v = vec3(key, fallback);
    for (int i = 0; i < 3; ++i)
        if (v[i] < lo || v[i] > hi)
            fail(key, "element " + std::to_string(i) + " must be in [" + number_text(lo) + ", " + number_text(hi) +
                          "], got " + value_.at(key)[i].dump());
    return v;
}

std::string JsonObject::path_string(const char* key) {
    std::string s = string(key, "");
    if (s.find('\0') != std::string::npos) fail(key, "contains a NUL character; a file name cannot");
    return s;
}

Point64 JsonObject::point(const char* key, Point64 fallback) {
    if (!has(key)) return fallback;
    float f[3];  // the checks: three numbers, each finite as a float
    floats(key, f, 3);
    Point64 p;
    doubles(key, p.data(), 3);
    return p;
}

Transform64 JsonObject::transform(const char* key) {
    float f[16];  // finite as floats: the linear part becomes float, the translation stays close
    floats(key, f, 16);
    if (f[12] != 0 || f[13] != 0 || f[14] != 0 || f[15] != 1)
        fail(key, "last row must be 0 0 0 1 (an affine transform)");
    double d[16];
    doubles(key, d, 16);
    Transform64 t;
    for (int i = 0; i < 12; ++i) t.m[i / 4][i % 4] = d[i];
    if (!(t.relative_to({0, 0, 0}).uniform_scale() > 0)) fail(key, "is singular");  // as floats
    return t;
}

Transform64 JsonObject::placement() {
    if (has("matrix_world")) {
        if (has("position") || has("look_at"))
            fail("matrix_world", "give either matrix_world or position + look_at, not both");
        return transform("matrix_world");
    }
    if (!has("position")) fail(nullptr, "needs matrix_world or position + look_at");
    const Point64 position = point("position", {});
    if (!has("look_at")) fail("look_at", "is required with position");
    const Point64 target = point("look_at", {});
    const Vec3 up = vec3("up", Vec3(0, 0, 1));
    const Point64 view{target[0] - position[0], target[1] - position[1], target[2] - position[2]};
    if (std::sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]) < 1e-9)
        fail("look_at", "equals position");
    if (!(length(up) > 0)) fail("up", "has zero length; give the direction that should point up");
    return Transform64::look_at(position, target, to_point64(up));
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
