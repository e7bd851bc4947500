// Turns a surface hit into a scattering event: a model in a local frame plus the rule for
// where rays leave. Yarns with the BYSDF go through the implicit geometry first (plies,
// fibers, shadowing); a ray that meets no ply passes through the yarn. The explicit references
// (built by reference/explicit_models.h before the render): "ply" curves take the BYSDF at ply level with fiber detail from
// the same maps and leave through their own tube; "fiber" curves take the fiber BCSDF and leave
// through the fiber's local cylinder.
#pragma once
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "math/frame.h"
#include "math/ray.h"
#include "render/far_field.h"
#include "render/multiscale.h"
#include "render/scattering.h"
#include "scene/embree_scene.h"
#include "scene/scene.h"
#include "yarn/arc_length.h"
#include "yarn/curve_frames.h"
#include "yarn/fiber_maps.h"
#include "yarn/ply_crossings.h"
#include "yarn/ply_helix.h"

namespace purl {

// Multi-scale shading of a camera ray's hit (the ray carries differentials): the render's
// selector and two per-hit random numbers (h strata jitter, pass-through choice).
struct MultiscaleHitContext {
    const MultiscaleSelector* selector = nullptr;
    float u_strata = 0.5f, u_pass = 0.5f;
};

struct ShadingPoint {
    Frame frame;          // world <-> local; local +z is the shading normal
    Scattering bsdf = DiffuseBsdf{};  // the model, behind render/scattering.h
    bool holdout = false;
    Vec3 position;        // where light scatters (on a ply, for implicit yarns)

    // Surfaces: rays leave from `position`, moved off the surface along `surface_normal` by
    // its float error `error` (math/ray_spawn.h).
    Vec3 surface_normal;
    float error = 0;
    // Implicit yarns and explicit plies: rays leave through the tube wall, wherever they cross it.
    const CurveFrames* tube = nullptr;
    uint32_t segment = 0;
    float t = 0;
    float yarn_radius = 0;
    // Implicit yarns with the traced ply crossing: the hit in the straight-yarn model
    // (world axes, yarn radii) and its yarn, for the plies a leaving ray crosses.
    const YarnDescription* yarn = nullptr;
    PlySection section;
    int ply = 0;
    // Explicit fibers: rays leave through the fiber as a cylinder (axis point, unit axis, m),
    // which parts from the bent fiber by up to curvature (1/m) x axial distance^2 / 2.
    float cylinder_radius = 0, cylinder_curvature = 0;
    Vec3 cylinder_point, cylinder_axis;

    struct Exit {
        Vec3 origin;     // where a ray toward wi starts
        float chord = 0; // path inside the yarn, in yarn radii (0 on surfaces)
        bool crossed = false;  // `plies` holds what the ray crosses (traced ply crossing)
        PlyCrossings plies;
        ScatterExit context() const { return {chord, crossed ? &plies : nullptr}; }  // what models read
    };
    Exit leave(Vec3 wi_world) const;

    // f and the density of `sample` toward wi in one evaluation, attenuated along `exit`
    // (leave(wi_world)): next-event estimation.
    BsdfEvalPdf eval_pdf(Vec3 wo_world, Vec3 wi_world, const Exit& exit) const;
    // A direction with its final f (attenuated along its exit, which `exit` receives) and pdf.
    std::optional<BsdfSample> sample(Vec3 wo_world, float u_lobe, Vec2 u, Exit& exit) const;
};

struct SurfaceInteraction {
    bool pass_through = false;  // the ray met no ply: it goes on, unchanged, from `continue_origin`
    Vec3 continue_origin;       // just past where it leaves the yarn
    ShadingPoint point;
    // Camera hits on BYSDF yarns shaded with a MultiscaleHitContext (multiscale_hit): the mode
    // used and the h samples traced (1 for near, 0 for the tabulated far field).
    bool multiscale_hit = false;
    MultiscaleMode multiscale_mode = MultiscaleMode::Near;
    int h_samples = 0;
    // The ply hit (BYSDF yarns in near and multi mode: the ray's own ply hit, else the h sample
    // nearest it; explicit "ply" yarns; -1 otherwise), for the PlyIndex and PlyUV passes.
    int ply_index = -1;
    float u_ply = 0, v_ply = 0;  // rad, m
};

// Per-scene shading data built once: curve frames and fiber maps for BYSDF yarn sets.
class SurfaceShader {
public:
    explicit SurfaceShader(const SceneDesc& scene);
    ~SurfaceShader();
    // `multiscale`: only for camera rays (with differentials); deeper rays shade near, with
    // their ray cone's width at the hit (render/ray_cone.h, m) choosing how exactly to find the ply.
    SurfaceInteraction shade(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext* multiscale = nullptr,
                             float cone_width = 0) const;
    size_t memory_bytes() const;  // frames and maps

private:
    struct YarnSetData {
        std::vector<CurveFrames> frames;   // per curve
        std::unique_ptr<FiberMaps> maps;   // shared by the set's curves
        // "ply" sets: the yarns the plies came from, per yarn curve.
        std::vector<CurveFrames> yarn_frames;
        std::vector<ArcLengthIndex> yarn_arc;
        // The ply and fiber twist rates of each yarn curve: the "bysdf" sets' own curves, the
        // "ply" sets' origin yarns (set once, not per hit).
        std::vector<YarnTwist> yarn_twist;
        std::unique_ptr<FiberBcsdf> fiber;  // "fiber" sets: the per-material BCSDF
        // Per-yarn colours (YarnCurves::colors): the material recoloured once per distinct
        // colour, and which of those each yarn curve uses. Empty: every curve uses the material.
        std::vector<BysdfParams> colored_bysdf;
        std::vector<uint32_t> colored_of_curve;
        const BysdfParams& bysdf(const MaterialDesc& m, size_t yarn_curve) const {
            return colored_of_curve.empty() ? m.bysdf : colored_bysdf[colored_of_curve[yarn_curve]];
        }
    };
    void shade_ply(const SurfaceHit& hit, const Ray& ray, const YarnSetData& data, const MaterialDesc& m,
                   SurfaceInteraction& out) const;
    // A camera hit on a BYSDF yarn in multi or far mode (false: shade it near).
    bool shade_multiscale(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext& context,
                          const YarnTubeHit& tube_hit, SurfaceInteraction& out) const;
    // Far mode with the tabulated far field: no implicit query; scatters at the tube entry.
    void shade_far(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext& context,
                   const FarFieldTable& table, const CentrelineProjection& axis, SurfaceInteraction& out) const;
    void shade_placeholder(const SurfaceHit& hit, Vec3 normal, const MaterialDesc& m, ShadingPoint& sp) const;
    void shade_fiber(const SurfaceHit& hit, Vec3 wo, Vec3 normal, const YarnSetData& data, ShadingPoint& sp) const;
    // A ray that meets no ply: on through the tube, out at `distance` from the hit.
    static void pass_through(const SurfaceHit& hit, const Ray& ray, const CurveFrames& frames, float distance,
                             SurfaceInteraction& out);
    static void recolor_bysdf(const BysdfParams& material, const std::vector<Vec3>& colors, YarnSetData& data);
    const SceneDesc& scene_;
    std::vector<YarnSetData> yarn_sets_;
    std::vector<uint32_t> curve_key_base_;
    PlyTraceOptions ply_trace_;     // render.ply_method
    PlyTraceOptions coarse_trace_;  // bounce rays with wide cones
};

}  // namespace purl
