// The scene as every front door (CLI, Python, Blender) describes it: plain data, no Embree.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "base/registry.h"
#include "bsdf/bysdf_params.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "bsdf/placeholder.h"
#include "math/transform.h"
#include "scene/curves.h"
#include "scene/explicit_options.h"
#include "scene/multiscale_settings.h"
#include "yarn/yarn_description.h"

namespace purl {

enum class SensorFit { Auto, Horizontal, Vertical };

// How yarns are represented: implicit plies and fibers (the BYSDF), or the explicit
// references generated from the same curves and description (reference/explicit_models.h).
// Named, in this order, by yarn_models() (base/registry.h).
enum class YarnModel { Bysdf, Ply, Fiber };

struct CameraDesc {
    Transform to_world;          // camera looks down its local -Z, +Y up (Blender)
    float lens_mm = 50.0f;
    float sensor_width_mm = 36.0f;
    float sensor_height_mm = 24.0f;
    SensorFit sensor_fit = SensorFit::Auto;
    float shift_x = 0.0f, shift_y = 0.0f;  // in units of the fitted image side
    float clip_start = 0.1f, clip_end = 1000.0f;  // m
};

struct FilmDesc {
    int width = 640, height = 480;  // px
    float pixel_aspect_x = 1.0f, pixel_aspect_y = 1.0f;
    bool transparent = false;
};

// Defaults as declared in render_settings() (base/registry.h; test_registry keeps them equal).
struct RenderSettings {
    int spp = 64;
    // Renders samples first_sample .. first_sample + spp - 1 of every pixel, so renders of
    // consecutive ranges average to one render of them all (progressive passes).
    int first_sample = 0;
    uint64_t seed = 0;
    int max_depth = 8;
    int threads = 0;      // 0: all cores
    float clamp = 0.0f;   // 0: off
    YarnModel model = YarnModel::Bysdf;
    MultiscaleSettings multiscale = default_multiscale_settings();  // camera hits on BYSDF yarns
    ExplicitOptions explicit_options;  // the ply and fiber models' sampling and memory budget
    // How the BYSDF finds the ply under a tube hit: elliptical (exact, default), local (the
    // yarn straightened at the hit: faster, exact only on straight yarns), circular (comparison).
    PlyCrossSection ply_method = PlyCrossSection::elliptical;
    // Benchmark baseline (bench/): true traces camera rays only and shades every first hit a
    // constant grey, to measure traversal alone (no implicit plies, lights or bounces).
    bool trace_only = false;
    // Denoise the image with Open Image Denoise after the last sample (render/denoise.h).
    bool denoise = false;
    // Cycles' Filter Glossy: after a bounce of low pdf, glossy lobes are roughened by this much
    // (render/path_regularization.h); 0 turns it off.
    float filter_glossy = 1.0f;
};

enum class LightType { Point, Spot, Sun, Area };
enum class AreaShape { Square, Rectangle, Disk, Ellipse };

struct LightDesc {
    LightType type = LightType::Point;
    Transform to_world;  // spot, sun and area lights emit along local -Z
    Vec3 color{1.0f};
    float power = 1000.0f;    // W (point, spot, area)
    float radius = 0.0f;      // m (point, spot)
    float spot_size = 0.785398f;  // rad, full cone angle
    float spot_blend = 0.15f;
    float strength = 1.0f;    // W/m^2 (sun)
    float angle = 0.0f;       // rad, angular diameter (sun)
    AreaShape shape = AreaShape::Square;
    float size = 1.0f, size_y = 1.0f;  // m
};

struct WorldDesc {
    Vec3 color{0.0f};
    float strength = 1.0f;
    std::string texture;  // lat-long image path, empty for none
    float rotation_z = 0.0f;
};

// Where each curve of an explicit ply set (material "ply", made by reference/explicit_models.h)
// lies along the yarn it was made from: the shader looks the fiber maps up as the BYSDF does.
struct PlyCurveOrigin {
    uint32_t yarn_curve = 0;  // curve index in PlyOrigins::yarns
    int32_t ply = 0;          // 0 .. N-1
    float arc_start = 0;      // m: yarn arc length (v_yarn) at the ply curve's first knot
    float arc_step = 0;       // m of yarn arc length per knot (one segment of the ply curve)
};
struct PlyOrigins {
    std::shared_ptr<const YarnCurves> yarns;  // the centre-lines the plies twist around
    std::vector<PlyCurveOrigin> curves;       // one per curve of the set
    uint32_t key_base = 0;                    // migration key of yarns' curve 0 in the BYSDF scene
};

// A yarn set's scattering model, read once from the material's "model" where the scene is read
// ("bysdf", "placeholder", "fiber": explicit fibers); Ply is made by make_explicit_scene only.
enum class MaterialModel { Bysdf, Placeholder, Fiber, Ply };
const char* material_model_name(MaterialModel model);  // as the JSON format spells it

struct MaterialDesc {
    MaterialModel model = MaterialModel::Bysdf;
    PlaceholderParams placeholder;  // used by Placeholder
    BysdfParams bysdf;              // used by Bysdf and Ply: appearance
    YarnDescription yarn;           // used by Bysdf and Ply: plies and fibers
    FiberBcsdfParams fiber = default_fiber_bcsdf_params();  // used by Fiber and the fibers made from Bysdf
    PlyOrigins ply;                 // used by Ply
    MaterialDesc();
};

struct YarnSetDesc {
    std::string name;
    YarnCurves curves;  // world space, relative to SceneDesc::origin
    MaterialDesc material;
    int id = 0;
};

struct MeshDesc {
    std::string name;
    std::vector<Vec3> vertices;      // world space, relative to SceneDesc::origin
    std::vector<uint32_t> indices;   // 3 per triangle
    Vec3 color{0.8f};
    bool holdout = false;
};

// A file the scene reader opened or named besides the scene file itself (purl deps):
// what a render-farm worker needs beside the scene.
struct SceneFile {
    std::string role;   // the key naming it: "bcc", "obj", "texture", "preset_file", "preset" (a named preset)
    std::string place;  // where the scene names it, e.g. "yarns[0].bcc"
    std::string path;   // as resolved against the scene's folder (or found on the preset path)
};

struct SceneDesc {
    std::string source;  // file name or "<python>", for messages
    // World position of this description's zero: every position below is relative to it. The
    // scene reader picks it near the cloth and subtracts it in double (scene/scene_json.cpp), so
    // a scene far from the world origin keeps its precision as floats.
    Point64 origin{0, 0, 0};
    std::vector<SceneFile> files;  // in the order the scene names them
    CameraDesc camera;
    FilmDesc film;
    RenderSettings render;
    WorldDesc world;
    std::vector<LightDesc> lights;
    std::vector<YarnSetDesc> yarns;
    std::vector<MeshDesc> meshes;
};

}  // namespace purl
