#include "render/render_origin.h"

#include <memory>

namespace purl {

namespace {

struct Bounds {
    Vec3 lo{1e30f}, hi{-1e30f};
    void add(Vec3 p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    bool empty() const { return lo.x > hi.x; }
    Vec3 centre() const { return (lo + hi) * 0.5f; }
};

void move(Transform& t, Vec3 by) {
    for (int r = 0; r < 3; ++r) t.m[r][3] += by[r];
}

void move(YarnCurves& curves, Vec3 by) {
    for (Vec4& p : curves.control_points) p = Vec4(p.xyz() + by, p.w);
}

}  // namespace

Vec3 render_origin(const SceneDesc& scene) {
    Bounds yarns, meshes;
    for (const YarnSetDesc& y : scene.yarns)
        for (const Vec4& p : y.curves.control_points) yarns.add(p.xyz());
    for (const MeshDesc& m : scene.meshes)
        for (const Vec3& v : m.vertices) meshes.add(v);
    if (!yarns.empty()) return yarns.centre();
    if (!meshes.empty()) return meshes.centre();
    return scene.camera.to_world.translation();
}

void move_to_render_origin(SceneDesc& scene, Vec3 origin) {
    const Vec3 by = -origin;
    if (!is_finite(by) || is_black(by)) return;
    for (int i = 0; i < 3; ++i) scene.origin[i] += origin[i];
    move(scene.camera.to_world, by);
    for (LightDesc& l : scene.lights) move(l.to_world, by);
    for (YarnSetDesc& y : scene.yarns) {
        move(y.curves, by);
        if (PlyOrigins& o = y.material.ply; o.yarns) {  // shared with other scenes: moved as a copy
            auto moved = std::make_shared<YarnCurves>(*o.yarns);
            move(*moved, by);
            o.yarns = std::move(moved);
        }
    }
    for (MeshDesc& m : scene.meshes)
        for (Vec3& v : m.vertices) v += by;
}

}  // namespace purl
