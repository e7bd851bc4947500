#include "scene/scene_json.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "base/param_info.h"
#include "base/registry.h"
#include "bsdf/artist_params.h"
#include "scene/bcc.h"
#include "scene/json_reader.h"
#include "scene/material_preset.h"
#include "scene/obj_reader.h"
#include "scene/swatch.h"

namespace purl {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr float kHuge = 1e30f;

std::string resolve(const std::string& base_dir, const std::string& path) {
    if (path.empty() || fs::path(path).is_absolute() || base_dir.empty()) return path;
    return (fs::path(base_dir) / path).string();
}

// Positions are composed in double and made relative to the scene's origin before they become
// floats: a float is 1 mm apart at 1e4 m, two yarn radii. The first point placed becomes the
// origin (SceneDesc::origin): the first yarn point, else the first mesh vertex, else the camera
// (placed last), so the cloth keeps the precision it would have at the world origin.
struct LocalFrame {
    std::optional<Point64> origin;

    Vec3 local(const Point64& world) {
        if (!origin) origin = world;
        const Point64& o = *origin;
        return {float(world[0] - o[0]), float(world[1] - o[1]), float(world[2] - o[2])};
    }
    Transform local(const Transform64& placement) {
        if (!origin) origin = placement.translation();
        return placement.relative_to(*origin);
    }
};

// The path `key` names, resolved, and noted in `files` under that key (what `purl deps` lists).
std::string named_file(JsonObject& o, const char* key, const std::string& base_dir, std::vector<SceneFile>& files) {
    const std::string path = resolve(base_dir, o.path_string(key));
    if (!path.empty()) files.push_back({key, o.child_path(key), path});
    return path;
}

// Returns the camera's placement, which becomes local once the scene's origin is known.
Transform64 read_camera(JsonObject o, CameraDesc& cam) {
    const Transform64 placement = o.placement();
    cam.lens_mm = o.number("lens", cam.lens_mm, 0.01f, 1e5f);
    cam.sensor_width_mm = o.number("sensor_width", cam.sensor_width_mm, 0.01f, 1e4f);
    cam.sensor_height_mm = o.number("sensor_height", cam.sensor_height_mm, 0.01f, 1e4f);
    const std::string fit = o.choice("sensor_fit", "AUTO", {"AUTO", "HORIZONTAL", "VERTICAL"});
    cam.sensor_fit = fit == "AUTO" ? SensorFit::Auto
                                   : (fit == "HORIZONTAL" ? SensorFit::Horizontal : SensorFit::Vertical);
    cam.shift_x = o.number("shift_x", 0.0f, -100.0f, 100.0f);
    cam.shift_y = o.number("shift_y", 0.0f, -100.0f, 100.0f);
    cam.clip_start = o.number("clip_start", cam.clip_start, 0.0f, kHuge);
    cam.clip_end = o.number("clip_end", cam.clip_end, 0.0f, kHuge);
    if (!(cam.clip_end > cam.clip_start)) o.fail("clip_end", "must be greater than clip_start");
    o.finish();
    return placement;
}

void read_film(JsonObject o, FilmDesc& film) {
    film.width = o.integer("width", film.width, 1, 32768);
    film.height = o.integer("height", film.height, 1, 32768);
    film.pixel_aspect_x = o.number("pixel_aspect_x", 1.0f, 1e-3f, 1e3f);
    film.pixel_aspect_y = o.number("pixel_aspect_y", 1.0f, 1e-3f, 1e3f);
    film.transparent = o.boolean("transparent", false);
    o.finish();
}

void read_multiscale(JsonObject o, MultiscaleSettings& m);  // below read_params

void read_explicit_options(JsonObject o, ExplicitOptions& e) {
    e.ply_tolerance = o.number("ply_tolerance", e.ply_tolerance, 1e-5f, 0.5f);
    e.fiber_tolerance = o.number("fiber_tolerance", e.fiber_tolerance, 1e-4f, 2.0f);
    e.curvature_quantile = o.number("curvature_quantile", e.curvature_quantile, 0.5f, 1.0f);
    const float budget_gib = o.number("memory_budget_gib", float(e.memory_budget_bytes / (1u << 30)), 1e-4f, 1024.0f);
    e.memory_budget_bytes = double(budget_gib) * double(1u << 30);
    o.finish();
}

// A render setting of base/registry.h: its range and default from the table.
int read_setting_integer(JsonObject& o, const char* name) {
    const ParamInfo& s = render_setting(name);
    return o.integer(name, int(s.default_value[0]), int(s.min_value), int(s.max_value));
}
float read_setting_number(JsonObject& o, const char* name) {
    const ParamInfo& s = render_setting(name);
    return o.number(name, s.default_value[0], float(s.min_value), float(s.max_value));
}
float read_setting_choice(JsonObject& o, const char* name) {
    const ChoiceList& list = *render_setting(name).choices;
    return find_choice(list, o.choice(name, list.default_name, choice_names(list)))->value;
}

void read_render(JsonObject o, RenderSettings& r) {
    r.spp = read_setting_integer(o, "spp");
    r.seed = static_cast<uint64_t>(read_setting_integer(o, "seed"));
    r.max_depth = read_setting_integer(o, "max_depth");
    r.threads = read_setting_integer(o, "threads");
    r.clamp = read_setting_number(o, "clamp");
    r.model = static_cast<YarnModel>(read_setting_choice(o, "model"));
    if (o.has("multiscale")) read_multiscale(o.object("multiscale"), r.multiscale);
    if (o.has("explicit")) read_explicit_options(o.object("explicit"), r.explicit_options);
    r.trace_only = read_setting_choice(o, "integrator") == find_choice(integrators(), "trace")->value;
    r.ply_method = static_cast<PlyCrossSection>(read_setting_choice(o, "ply_method"));
    r.denoise = o.boolean("denoise", false);
    r.filter_glossy = read_setting_number(o, "filter_glossy");
    o.finish();
}

void read_world(JsonObject o, WorldDesc& w, const std::string& base_dir, std::vector<SceneFile>& files) {
    w.color = o.vec3("color", w.color);
    w.strength = o.number("strength", 1.0f, 0.0f, kHuge);
    w.texture = named_file(o, "texture", base_dir, files);
    w.rotation_z = o.number("rotation_z", 0.0f, -kHuge, kHuge);
    if (w.color.x < 0 || w.color.y < 0 || w.color.z < 0) o.fail("color", "must not be negative");
    o.finish();
}

// `placement` becomes the light's to_world once the scene's origin is known.
LightDesc read_light(JsonObject o, Transform64& placement) {
    LightDesc l;
    const std::string type = o.choice("type", "", {"point", "spot", "sun", "area"});
    l.type = type == "point" ? LightType::Point
             : type == "spot" ? LightType::Spot
             : type == "sun"  ? LightType::Sun
                              : LightType::Area;
    placement = o.placement();
    l.color = o.vec3("color", Vec3(1.0f));
    if (l.color.x < 0 || l.color.y < 0 || l.color.z < 0) o.fail("color", "must not be negative");
    if (l.type == LightType::Sun) {
        l.strength = o.number("strength", 1.0f, 0.0f, kHuge);
        l.angle = o.number("angle", 0.0f, 0.0f, kPi);
    } else {
        l.power = o.number("power", 1000.0f, 0.0f, kHuge);
    }
    if (l.type == LightType::Point || l.type == LightType::Spot)
        l.radius = o.number("radius", 0.0f, 0.0f, kHuge);
    if (l.type == LightType::Spot) {
        l.spot_size = o.number("spot_size", l.spot_size, 1e-4f, kPi);
        l.spot_blend = o.number("spot_blend", l.spot_blend, 0.0f, 1.0f);
    }
    if (l.type == LightType::Area) {
        const std::string shape = o.choice("shape", "SQUARE", {"SQUARE", "RECTANGLE", "DISK", "ELLIPSE"});
        l.shape = shape == "SQUARE" ? AreaShape::Square
                  : shape == "RECTANGLE" ? AreaShape::Rectangle
                  : shape == "DISK" ? AreaShape::Disk
                                    : AreaShape::Ellipse;
        l.size = o.number("size", 1.0f, 1e-6f, kHuge);
        const bool two_sizes = l.shape == AreaShape::Rectangle || l.shape == AreaShape::Ellipse;
        l.size_y = two_sizes ? o.number("size_y", l.size, 1e-6f, kHuge) : l.size;
    }
    o.finish();
    return l;
}

// Reads every declared parameter of a table into the struct at `params`.
template <class Params>
void read_params(JsonObject& o, const std::vector<ParamInfo>& table, Params& params) {
    for (const ParamInfo& info : table) {
        if (!o.has(info.name)) continue;
        float* field = param_field(params, info);
        if (info.components == 1) {
            *field = o.number(info.name, *field, info.min_value, info.max_value);
        } else {
            o.floats(info.name, field, info.components);
            for (int c = 0; c < info.components; ++c)
                if (field[c] < info.min_value || field[c] > info.max_value)
                    o.fail(info.name, "component " + std::to_string(c) + " must be in [" +
                                          number_text(info.min_value) + ", " +
                                          number_text(info.max_value) + "]");
        }
    }
}

// "multiscale": {"mode": "auto", "aggregation": "mixture", "multiscale_...": number, ...}
void read_multiscale(JsonObject o, MultiscaleSettings& m) {
    m.mode = *parse_multiscale_mode(o.choice("mode", multiscale_mode_name(m.mode), choice_names(multiscale_modes())));
    m.aggregation = *parse_multiscale_aggregation(o.choice(
        "aggregation", multiscale_aggregation_name(m.aggregation), choice_names(multiscale_aggregations())));
    read_params(o, multiscale_param_table(), m);
    check_multiscale_settings(m, o.file(), o.path());
    o.finish();
}

// The fiber BCSDF's parameters: an optional "preset" (Khungurn et al.'s fits), then overrides.
void read_fiber_params(JsonObject& o, FiberBcsdfParams& p) {
    if (o.has("preset")) {
        const std::string name = o.string("preset", "");
        try {
            p = fiber_bcsdf_preset(name);
        } catch (const InputError& e) {
            o.fail("preset", e.reason());
        }
    }
    read_params(o, fiber_bcsdf_param_table(), p);
}

MaterialDesc read_material(JsonObject o) {
    MaterialDesc m;
    const std::string model =
        o.choice("model", material_models().default_name, choice_names(material_models()));
    m.model = MaterialModel(int(find_choice(material_models(), model)->value));
    if (m.model == MaterialModel::Placeholder) {
        read_params(o, placeholder_param_table(), m.placeholder);
    } else if (m.model == MaterialModel::Fiber) {
        read_fiber_params(o, m.fiber);  // curves that already are fibers
    } else {
        if (o.has("fiber")) {  // for the fiber-based reference made from this yarn
            JsonObject f = o.object("fiber");
            read_fiber_params(f, m.fiber);
            f.finish();
        }
        read_params(o, bysdf_param_table(), m.bysdf);
        ArtistControls artist;  // "color", "sheen", ... on top of the physics (bsdf/artist_params.h)
        artist.has_color = o.has("color");
        read_params(o, artist_param_table(), artist);
        m.bysdf = apply_artist_controls(m.bysdf, artist);
        if (o.has("yarn")) {
            JsonObject y = o.object("yarn");
            if (y.has("preset")) m.yarn = yarn_preset(y.string("preset", ""));
            read_params(y, yarn_description_params(), m.yarn);
            y.finish();
            check_yarn_description(m.yarn, y.file(), y.path());
        }
    }
    o.finish();
    return m;
}

// A yarn set's "material", with "preset"/"preset_file" resolved (scene/material_preset.h):
// the preset is checked on its own first, so its mistakes are reported against its own file.
MaterialDesc read_material_entry(JsonObject& yarn_set, const std::string& base_dir, std::vector<SceneFile>& files) {
    JsonObject given = yarn_set.object("material");
    const json& value = yarn_set.raw("material");
    if (!value.is_object() || !material_uses_preset(value)) return read_material(given);
    const MaterialPreset preset = load_material_preset(value, given.file(), given.path(), base_dir);
    const std::string key = value.contains("preset_file") ? "preset_file" : "preset";
    files.push_back({key, given.path() + "." + key, preset.path});
    read_material(JsonObject(preset.material, "material", preset.path));
    const json merged = merge_material(preset.material, value);
    return read_material(JsonObject(merged, given.path(), given.file()));
}

void place_curves(YarnCurves& curves, const Transform64& t, LocalFrame& frame) {
    const float scale = float(t.uniform_scale());
    for (Vec4& p : curves.control_points) p = Vec4(frame.local(t.point(to_point64(p.xyz()))), p.w * scale);
}

// "curve_colors": [[r, g, b], ...], one linear RGB colour per curve of the set.
void read_curve_colors(JsonObject& o, YarnCurves& curves) {
    const json& list = o.raw("curve_colors");
    const std::string place = o.child_path("curve_colors");
    if (!list.is_array() || list.size() != curves.curve_count())
        o.fail("curve_colors", "must be a list of " + std::to_string(curves.curve_count()) +
                                   " [r, g, b] colours, one per curve");
    curves.colors.clear();
    for (size_t c = 0; c < list.size(); ++c) {
        const json& rgb = list[c];
        const std::string where = place + "[" + std::to_string(c) + "]";
        if (!rgb.is_array() || rgb.size() != 3 || !rgb[0].is_number() || !rgb[1].is_number() || !rgb[2].is_number())
            throw InputError(o.file(), where, "must be [r, g, b], three numbers");
        const Vec3 color(rgb[0].get<float>(), rgb[1].get<float>(), rgb[2].get<float>());
        check_curve_color(color, o.file(), where);
        curves.colors.push_back(color);
    }
}

YarnSetDesc read_yarn_set(JsonObject o, const std::string& base_dir, const ExternalArrays* arrays,
                          std::vector<SceneFile>& files, LocalFrame& frame) {
    YarnSetDesc y;
    y.name = o.string("name", o.path());
    y.id = o.integer("id", 0, 0, 1 << 20);
    const int sources = int(o.has("bcc")) + int(o.has("arrays")) + int(o.has("generate"));
    if (sources != 1) o.fail(nullptr, "needs exactly one of bcc, arrays, generate");
    if (o.has("bcc")) {
        const float radius = o.required_number("radius", 1e-9f, kHuge);
        y.curves = load_bcc(named_file(o, "bcc", base_dir, files), radius);
    } else if (o.has("arrays")) {
        const std::string name = o.string("arrays", "");
        if (!arrays || !arrays->yarns) o.fail("arrays", "names in-memory arrays, but none were given");
        y.curves = arrays->yarns(name);
        const float scale = o.number("radius_scale", 1.0f, 1e-9f, kHuge);
        for (Vec4& p : y.curves.control_points) p.w *= scale;
    } else {
        JsonObject g = o.object("generate");
        SwatchOptions options;
        const SwatchKind kind = parse_swatch_kind(g.string("kind", "knit"));
        options.yarn_radius = g.number("radius", options.yarn_radius, 1e-9f, kHuge);
        options.courses = g.integer("courses", options.courses, 1, 10000);
        options.wales = g.integer("wales", options.wales, 1, 10000);
        options.warps = g.integer("warps", options.warps, 1, 10000);
        options.wefts = g.integer("wefts", options.wefts, 1, 10000);
        options.spacing = g.number("spacing", 0.0f, 0.0f, kHuge);
        options.twill_over = g.integer("twill_over", options.twill_over, 1, 16);
        options.twill_under = g.integer("twill_under", options.twill_under, 1, 16);
        g.finish();
        y.curves = generate_swatch(kind, options);
    }
    place_curves(y.curves, o.has("matrix_world") ? o.transform("matrix_world") : Transform64{}, frame);
    if (o.has("curve_colors")) read_curve_colors(o, y.curves);
    if (o.has("material")) y.material = read_material_entry(o, base_dir, files);
    o.finish();
    validate_curves(y.curves, o.file() + ": " + o.path());
    return y;
}

MeshDesc read_mesh(JsonObject o, const std::string& base_dir, const ExternalArrays* arrays,
                   std::vector<SceneFile>& files, LocalFrame& frame) {
    MeshDesc m;
    std::vector<Point64> given;  // vertices written in the scene, kept in double
    m.name = o.string("name", o.path());
    const int sources = int(o.has("obj")) + int(o.has("arrays")) + int(o.has("vertices"));
    if (sources != 1) o.fail(nullptr, "needs exactly one of obj, arrays, vertices + triangles");
    if (o.has("obj")) {
        read_obj(named_file(o, "obj", base_dir, files), m);
    } else if (o.has("arrays")) {
        const std::string name = o.string("arrays", "");
        if (!arrays || !arrays->meshes) o.fail("arrays", "names in-memory arrays, but none were given");
        m = arrays->meshes(name);
    } else {
        const json& v = o.raw("vertices");
        const json& t = o.raw("triangles");
        if (!v.is_array() || !t.is_array()) o.fail("vertices", "vertices and triangles must be arrays");
        try {
            for (const json& p : v)
                given.push_back({p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()});
            m.vertices.resize(given.size());
            for (const json& tri : t)
                for (int k = 0; k < 3; ++k) {
                    // Only non-negative whole numbers: a float such as 2e31 does not convert to an index.
                    const json& index = tri.at(k);
                    if (!index.is_number_unsigned()) o.fail("triangles", "triangle indices must be whole numbers >= 0");
                    const uint64_t i = index.get<uint64_t>();
                    m.indices.push_back(i < given.size() ? static_cast<uint32_t>(i) : UINT32_MAX);  // checked below
                }
        } catch (const json::exception&) {
            o.fail("vertices", "vertices must be [x,y,z] numbers and triangles [i,j,k] indices");
        }
    }
    for (uint32_t index : m.indices)
        if (index >= m.vertices.size()) o.fail(nullptr, "triangle index out of range");
    const Transform64 t = o.has("matrix_world") ? o.transform("matrix_world") : Transform64{};
    for (size_t i = 0; i < m.vertices.size(); ++i)
        m.vertices[i] = frame.local(t.point(given.empty() ? to_point64(m.vertices[i]) : given[i]));
    // After matrix_world: finite numbers times a large scale can overflow to infinity.
    for (const Vec3& p : m.vertices)
        if (!is_finite(p)) o.fail(nullptr, "vertex position is not finite (after matrix_world)");
    m.color = o.vec3_in("color", m.color, 0, 1);  // albedo: a negative channel made every sample invalid
    m.holdout = o.boolean("holdout", false);
    o.finish();
    return m;
}

}  // namespace

YarnModel parse_yarn_model(const std::string& name, const std::string& source) {
    return static_cast<YarnModel>(parse_choice(yarn_models(), name, source, "model"));
}

PlyCrossSection parse_ply_method(const std::string& name, const std::string& source) {
    return static_cast<PlyCrossSection>(parse_choice(ply_methods(), name, source, "ply_method"));
}

SceneDesc parse_scene_text(const std::string& text, const std::string& source,
                           const std::string& base_dir, const ExternalArrays* arrays) {
    const json root = parse_json_text(text, source);
    SceneDesc scene;
    scene.source = source;
    JsonObject o(root, "", source);
    o.integer("version", 1, 1, 1);
    LocalFrame frame;
    const Transform64 camera = read_camera(o.object("camera"), scene.camera);
    if (o.has("film")) read_film(o.object("film"), scene.film);
    if (o.has("render")) read_render(o.object("render"), scene.render);
    if (o.has("world")) read_world(o.object("world"), scene.world, base_dir, scene.files);
    std::vector<Transform64> lights;
    for (JsonObject& l : o.array_of_objects("lights")) scene.lights.push_back(read_light(l, lights.emplace_back()));
    for (JsonObject& y : o.array_of_objects("yarns"))
        scene.yarns.push_back(read_yarn_set(y, base_dir, arrays, scene.files, frame));
    for (JsonObject& m : o.array_of_objects("meshes"))
        scene.meshes.push_back(read_mesh(m, base_dir, arrays, scene.files, frame));
    o.finish();
    scene.camera.to_world = frame.local(camera);
    for (size_t i = 0; i < lights.size(); ++i) scene.lights[i].to_world = frame.local(lights[i]);
    scene.origin = *frame.origin;
    if (scene.yarns.empty() && scene.meshes.empty())
        throw InputError(source, "", "the scene has no yarns and no meshes");
    return scene;
}

SceneDesc parse_view_text(const std::string& text, const std::string& source) {
    const json root = parse_json_text(text, source);
    SceneDesc scene;
    scene.source = source;
    JsonObject o(root, "", source);
    LocalFrame frame;
    scene.camera.to_world = frame.local(read_camera(o.object("camera"), scene.camera));
    scene.origin = *frame.origin;
    if (o.has("film")) read_film(o.object("film"), scene.film);
    return scene;
}

SceneDesc load_scene_file(const std::string& path) {
    // Checked before reading: a FIFO would block, and parsing a file of gigabytes would take
    // about ten times its size in memory (docs/robustness.md).
    constexpr uintmax_t kMaxSceneBytes = uintmax_t(256) << 20;
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw InputError(path, "", "not a regular file");
    const uintmax_t bytes = fs::file_size(path, ec);
    if (!ec && bytes > kMaxSceneBytes)
        throw InputError(path, "", "file too large: " + std::to_string(bytes) + " bytes, scene files may have at most " +
                                       std::to_string(kMaxSceneBytes) + " (256 MiB; give big meshes and yarns as OBJ/BCC files)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file");
    std::string text(static_cast<size_t>(ec ? 0 : bytes), '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    if (!in) throw InputError(path, "", "cannot read file");
    return parse_scene_text(text, path, fs::path(path).parent_path().string());
}

}  // namespace purl
