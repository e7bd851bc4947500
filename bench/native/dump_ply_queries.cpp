// Writes the implicit ply query's answer for the camera rays of the benchmark scenes, every
// method, so that two builds (is a change bit-identical?) or two methods (how often do they
// agree?) can be compared ray by ray with tools/compare_ply_queries.py. Not a benchmark: it
// times nothing.
//
//   dump_ply_queries OUT_PREFIX [RAYS_PER_SCENE (default 100000)]
//
// Writes OUT_PREFIX.json (methods, fields, scenes) and OUT_PREFIX.<scene>.bin: for every ray
// that meets a yarn tube, for every method in order, the PlyHit fields below as float32, and
// the ray's film position in pixels (tools/draw_cloth_accuracy.py draws maps from it).
// Methods: the three of render.ply_method; `straight`, the local method with the yarn
// straightened at the hit (curvature zero): what any answer precomputed for straight yarns
// would give; and `explicit`, the truth: the same yarn's plies as exact helix tubes
// (ExplicitPlies), traced from the tube entry to the tube exit, N_i by one trace per ply.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "math/rng.h"
#include "reference/explicit_plies.h"
#include "reference/explicit_sampling.h"
#include "reference/ply_validation.h"
#include "render/camera.h"
#include "scene/embree_scene.h"
#include "scene/scene_json.h"
#include "yarn/implicit_plies.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

const char* const kScenes[] = {"glove_close", "glove_far", "knit_tube"};
const char* const kMethods[] = {"elliptical", "local", "circular", "straight", "explicit"};
constexpr int kMethodCount = sizeof(kMethods) / sizeof(kMethods[0]);
const char* const kFields[] = {"hit",      "ply",      "plies_crossed", "point_x", "point_y", "point_z",
                               "normal_x", "normal_y", "normal_z",      "tangent_x", "tangent_y", "tangent_z",
                               "distance", "exit_distance", "u_ply",   "v_ply",   "u_yarn",  "v_yarn",
                               "arrangement_azimuth", "segment", "t", "iterations", "converged", "radius",
                               "film_x", "film_y"};
constexpr int kFieldCount = sizeof(kFields) / sizeof(kFields[0]);

// `method` indexes kMethods (all but `explicit`).
PlyHit query(const CurveFrames& frames, const YarnDescription& d, const YarnTubeHit& hit, int method,
             PlySearchStats& spent) {
    const YarnTwist twist = yarn_twist(frames, d);
    PlyTraceOptions options;  // elliptical, the default
    if (method == 1 || method == 3) options.cross_section = PlyCrossSection::local;
    if (method == 2) options.cross_section = PlyCrossSection::circular;
    if (method != 3) return trace_plies({frames, d, twist, hit}, options, &spent);
    // straight: the local method around the hit's cross-section with its curvature taken away
    CentrelineProjection at = project_to_centreline(frames, hit.point, hit.segment, hit.t);
    at.point.curvature = Vec3(0.0f);
    return trace_plies({frames, d, twist, hit, &at}, options, &spent);
}

// One method's answer for the ray through film position (x, y), in pixels.
void write_hit(std::FILE* out, const PlyHit& h, const PlySearchStats& spent, float radius, float x, float y) {
    const float fields[kFieldCount] = {
        float(h.hit),  float(h.ply),  float(h.plies_crossed), h.point.x,   h.point.y,   h.point.z,
        h.normal.x,    h.normal.y,    h.normal.z,             h.tangent.x, h.tangent.y, h.tangent.z,
        h.distance,    h.exit_distance, h.u_ply,              h.v_ply,     h.u_yarn,    h.v_yarn,
        h.arrangement_azimuth, float(h.segment), h.t, float(spent.evaluations), float(spent.converged), radius, x, y};
    std::fwrite(fields, sizeof fields, 1, out);
}

int dump_scene(const std::string& prefix, const char* name, int rays) {
    const SceneDesc scene = load_scene_file(std::string(PURL_SOURCE_DIR) + "/bench/scenes/" + name + ".json");
    const EmbreeScene tubes(scene);
    std::vector<std::vector<CurveFrames>> frames;
    for (const YarnSetDesc& set : scene.yarns) frames.push_back(yarn_set_frames(set.curves));
    const Camera camera(scene.camera, scene.film);
    const std::string path = prefix + "." + name + ".bin";
    std::FILE* out = std::fopen(path.c_str(), "wb");
    if (!out) {
        std::fprintf(stderr, "dump_ply_queries: cannot write %s\n", path.c_str());
        return 1;
    }
    // Per curve, built on first use.
    std::map<std::pair<uint32_t, uint32_t>, std::unique_ptr<ExplicitPlies>> explicit_plies;
    Rng rng(11, 5);
    int written = 0;
    for (long tries = 0; written < rays && tries < 100L * rays; ++tries) {
        const float x = rng.next_float() * scene.film.width, y = rng.next_float() * scene.film.height;
        const Ray ray = camera.generate_ray(x, y);
        SurfaceHit hit;
        if (!tubes.intersect(ray, hit) || hit.kind != SurfaceKind::Yarn) continue;
        const CurveFrames& curve = frames[hit.object][hit.curve];
        const YarnDescription& d = scene.yarns[hit.object].material.yarn;
        const YarnTubeHit tube_hit{ray.origin, ray.direction, hit.position, hit.segment, hit.u};
        for (int method = 0; method + 1 < kMethodCount; ++method) {
            PlySearchStats spent;
            const PlyHit h = query(curve, d, tube_hit, method, spent);
            write_hit(out, h, spent, curve.reference_radius(), x, y);
        }
        auto& plies = explicit_plies[{hit.object, hit.curve}];
        if (!plies) plies = std::make_unique<ExplicitPlies>(curve, d);
        PlySearchStats spent;
        const PlyHit reference = explicit_ply_answer(curve, *plies, d.plies(), tube_hit, &spent);
        write_hit(out, reference, spent, curve.reference_radius(), x, y);
        ++written;
    }
    std::fclose(out);
    std::printf("%s: %d rays -> %s\n", name, written, path.c_str());
    return 0;
}

std::string json_list(const char* const* items, int count) {
    std::string s = "[";
    for (int i = 0; i < count; ++i) s += std::string(i ? ", " : "") + "\"" + items[i] + "\"";
    return s + "]";
}

}  // namespace
}  // namespace purl

int main(int argc, char** argv) {
    using namespace purl;
    if (argc < 2) {
        std::fprintf(stderr, "usage: dump_ply_queries OUT_PREFIX [RAYS_PER_SCENE]\n");
        return 2;
    }
    const std::string prefix = argv[1];
    const int rays = argc > 2 ? std::atoi(argv[2]) : 100000;
    if (rays <= 0) {
        std::fprintf(stderr, "dump_ply_queries: RAYS_PER_SCENE must be a positive whole number, got \"%s\"\n", argv[2]);
        return 2;
    }
    std::FILE* meta = std::fopen((prefix + ".json").c_str(), "w");
    if (!meta) {
        std::fprintf(stderr, "dump_ply_queries: cannot write %s.json\n", prefix.c_str());
        return 1;
    }
    std::fprintf(meta, "{\"scenes\": %s, \"methods\": %s, \"fields\": %s}\n", json_list(kScenes, 3).c_str(),
                 json_list(kMethods, kMethodCount).c_str(), json_list(kFields, kFieldCount).c_str());
    std::fclose(meta);
    try {
        for (const char* name : kScenes)
            if (int status = dump_scene(prefix, name, rays)) return status;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dump_ply_queries: %s\n", e.what());
        return 1;
    }
    return 0;
}
