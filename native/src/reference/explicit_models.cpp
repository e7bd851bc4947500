#include "reference/explicit_models.h"

#include <cstdio>

#include "base/input_error.h"
#include "reference/fiber_curves.h"
#include "reference/ply_curves.h"

namespace purl {
namespace {

std::string set_place(const SceneDesc& scene, size_t y) {
    return "yarns[" + std::to_string(y) + "] (" + scene.yarns[y].name + ")";
}

std::string gib(double bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GiB", bytes / (1024.0 * 1024 * 1024));
    return text;
}

}  // namespace

ExplicitSize explicit_size(const SceneDesc& scene, YarnModel model, const ExplicitOptions& options) {
    ExplicitSize size;
    size.sets.resize(scene.yarns.size());
    if (model == YarnModel::Bysdf) return size;
    for (size_t y = 0; y < scene.yarns.size(); ++y) {
        const YarnSetDesc& set = scene.yarns[y];
        if (set.material.model != MaterialModel::Bysdf) continue;
        const YarnDescription& d = set.material.yarn;
        check_yarn_description(d, scene.source, set_place(scene, y) + ".material.yarn");
        const size_t per_curve = model == YarnModel::Ply ? size_t(d.plies()) : size_t(d.plies()) * d.fibers();
        ExplicitSetSize& s = size.sets[y];
        for (const CurveFrames& frames : yarn_set_frames(set.curves)) {
            const CurveSampling plan = model == YarnModel::Ply ? plan_ply_sampling(frames, d, options)
                                                               : plan_fiber_sampling(frames, d, options);
            s.curves += per_curve;
            s.control_points += per_curve * plan.control_points();
            s.segments += per_curve * plan.segments();
        }
        // Control points and segment table, Embree, per-curve tables; ply sets also keep frames
        // (one knot of 16 bytes per segment) and an origin per curve for the shader.
        s.bytes = s.control_points * sizeof(Vec4) + s.segments * (sizeof(uint32_t) + kEmbreeBytesPerSegment) +
                  s.curves * (3 * sizeof(uint32_t) + 1);
        if (model == YarnModel::Ply)
            s.bytes += s.segments * sizeof(Vec4) + s.curves * (sizeof(CurveFrames) + sizeof(PlyCurveOrigin));
        size.total.curves += s.curves;
        size.total.control_points += s.control_points;
        size.total.segments += s.segments;
        size.total.bytes += s.bytes;
    }
    return size;
}

SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model) {
    return make_explicit_scene(scene, model, scene.render.explicit_options);
}

SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model, const ExplicitOptions& options) {
    if (model == YarnModel::Bysdf) return scene;
    const MaterialModel material = model == YarnModel::Ply ? MaterialModel::Ply : MaterialModel::Fiber;
    const char* name = material_model_name(material);
    const ExplicitSize size = explicit_size(scene, model, options);
    if (double(size.total.bytes) > options.memory_budget_bytes || size.total.control_points >= (size_t(1) << 32)) {
        size_t largest = 0;
        for (size_t y = 1; y < size.sets.size(); ++y)
            if (size.sets[y].bytes > size.sets[largest].bytes) largest = y;
        throw InputError(scene.source, "render.model",
                         std::string("the ") + name + " model would need about " + gib(double(size.total.bytes)) +
                             " (" + std::to_string(size.total.curves) + " curves, " +
                             std::to_string(size.total.control_points) + " control points; " +
                             set_place(scene, largest) + " alone " + gib(double(size.sets[largest].bytes)) +
                             "), more than the budget of " + gib(options.memory_budget_bytes) +
                             "; render a smaller part of the scene or use fewer fibers per ply");
    }

    SceneDesc out;
    out.source = scene.source;
    out.origin = scene.origin;
    out.camera = scene.camera;
    out.film = scene.film;
    out.render = scene.render;
    out.world = scene.world;
    out.lights = scene.lights;
    out.meshes = scene.meshes;
    uint32_t key_base = 0;  // curve keys as the BYSDF's shader numbers them: across all sets
    for (size_t y = 0; y < scene.yarns.size(); ++y) {
        const YarnSetDesc& set = scene.yarns[y];
        const uint32_t set_key_base = key_base;
        key_base += static_cast<uint32_t>(set.curves.curve_count());
        if (set.material.model != MaterialModel::Bysdf) {
            out.yarns.push_back(set);
            continue;
        }
        YarnSetDesc e;
        e.name = set.name;
        e.id = set.id;
        e.material = set.material;
        e.material.model = material;
        const ExplicitSetSize& s = size.sets[y];
        YarnCurves& c = e.curves;
        c.control_points.reserve(s.control_points);
        c.segment_first.reserve(s.segments);
        c.curve_offsets.reserve(s.curves + 1);
        c.segment_offsets.reserve(s.curves + 1);
        c.closed.reserve(s.curves);
        c.curve_ids.reserve(s.curves);
        const YarnDescription& d = set.material.yarn;
        const std::vector<CurveFrames> frames = yarn_set_frames(set.curves);
        if (model == YarnModel::Ply) {
            e.material.ply.yarns = std::make_shared<const YarnCurves>(set.curves);
            e.material.ply.key_base = set_key_base;
            e.material.ply.curves.reserve(s.curves);
        }
        for (size_t k = 0; k < frames.size(); ++k) {
            const int32_t id = set.curves.curve_ids[k];
            if (model == YarnModel::Ply) {
                append_ply_curves(frames[k], d, plan_ply_sampling(frames[k], d, options), uint32_t(k), id, c,
                                  e.material.ply.curves);
            } else {
                append_fiber_curves(frames[k], d, plan_fiber_sampling(frames[k], d, options),
                                    set_key_base + uint32_t(k), id, c);
            }
        }
        out.yarns.push_back(std::move(e));
    }
    return out;
}

}  // namespace purl
