// The path tracer: camera rays with differentials, next-event estimation with multiple
// importance sampling, tiles in parallel on oneTBB. The image is a function of
// (scene, seed, spp) whatever the thread count.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "render/camera.h"
#include "render/lights.h"
#include "render/shading.h"
#include "scene/embree_scene.h"
#include "scene/scene.h"

namespace purl {

// Shared between the render and whoever watches it (CLI progress bar, Python, Blender).
struct RenderControl {
    std::atomic<bool> cancel{false};
    std::atomic<uint64_t> pixels_done{0};
    std::atomic<uint64_t> pixels_total{1};
    double progress() const {
        return static_cast<double>(pixels_done.load()) / static_cast<double>(std::max<uint64_t>(1, pixels_total.load()));
    }
};

struct RenderStats {
    double build_seconds = 0;      // Embree and light set-up
    double render_seconds = 0;
    uint64_t samples = 0;          // camera samples taken
    uint64_t rays = 0;             // all rays traced: camera, bounce and shadow
    double mean_path_length = 0;   // surface interactions per camera sample
    uint64_t invalid_samples = 0;  // NaN/Inf samples caught and dropped
    double denoise_seconds = 0;    // Open Image Denoise after the render (0 when off)
    size_t acceleration_bytes = 0;  // Embree's BVH and primitive data
    size_t shading_bytes = 0;       // curve frames and fiber maps
    size_t control_points = 0;
    size_t curves = 0;
    size_t peak_resident_bytes = 0; // of the whole process so far
    int threads = 0;
    // Multi-scale (render.multiscale): camera hits on BYSDF yarns by the mode that shaded them,
    // and the h samples those hits traced (near: 1 each).
    uint64_t hits_near = 0, hits_multi = 0, hits_far = 0, h_samples = 0;
    double mean_h_samples() const {
        const uint64_t hits = hits_near + hits_multi + hits_far;
        return hits ? double(h_samples) / double(hits) : 0.0;
    }
    // BYSDF evaluations (bsdf/bysdf.h), all of them: near shading, multi-scale components and
    // far-field misses alike. Per camera sample: bysdf_evaluations / samples.
    uint64_t bysdf_evaluations = 0;
    std::vector<std::string> warnings;  // e.g. far mode forced on yarns wider than a pixel
    double samples_per_second() const { return render_seconds > 0 ? samples / render_seconds : 0; }
};

struct RenderResult {
    RenderImage image;
    RenderStats stats;
    bool cancelled = false;
};

// Makes a (centred) scene explicit for render.model Ply or Fiber: reference/explicit_models.h's
// make_explicit_scene, passed in by the front doors so that render/ does not depend on the
// references; it only renders the scene they build.
using ExplicitSceneBuilder = SceneDesc (*)(const SceneDesc& scene, YarnModel model);

class Renderer {
public:
    // `make_explicit` is needed when scene.render.model is Ply or Fiber (InputError without).
    explicit Renderer(SceneDesc scene, ExplicitSceneBuilder make_explicit = nullptr);
    ~Renderer();
    // The scene as rendered: centred on its cloth (its `origin` says where that is in the
    // world, render/render_origin.h), explicit for ply/fiber renders.
    const SceneDesc& scene() const { return scene_; }
    const Camera& camera() const { return camera_; }

    // Another camera and film for the next renders: a viewport's view changes need no new
    // acceleration structure. Throws InputError for a film size render() would refuse.
    // Never while a render runs. The camera's placement is relative to `camera_origin` (the
    // SceneDesc::origin of the scene it was read with).
    void set_view(const CameraDesc& camera, const FilmDesc& film, const Point64& camera_origin);

    // Renders with the scene's settings; `control` may cancel it from another thread.
    RenderResult render(RenderControl& control) const;
    RenderResult render(const RenderSettings& settings, RenderControl& control) const;

private:
    struct PathTotals;
    void render_pixel(int x, int y, const RenderSettings& settings, const MultiscaleSelector& multiscale,
                      struct PixelResult& out, PathTotals& totals) const;

    SceneDesc scene_;
    Camera camera_;
    std::unique_ptr<EmbreeScene> geometry_;
    std::unique_ptr<Lights> lights_;
    std::unique_ptr<SurfaceShader> shader_;
    std::vector<uint32_t> yarn_id_base_;  // per yarn set: ids of earlier sets' curves
    double build_seconds_ = 0;
};

}  // namespace purl
