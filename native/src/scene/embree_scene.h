// The scene's geometry in Embree: yarns as round cubic B-spline curves with per-point
// radius (sharing the YarnCurves buffers, no copy), meshes as triangles.
#pragma once
#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>

#include "math/ray.h"
#include "scene/scene.h"

namespace purl {

enum class SurfaceKind : uint8_t { Yarn, Mesh };

struct SurfaceHit {
    float t = 0.0f;
    // On the surface as exactly as floats allow: rebuilt from the triangle's barycentrics, or
    // put at the curve's radius from its centre-line at u, not the ray's origin + t dir.
    Vec3 position;
    float error = 0.0f;     // bound on position's float error per coordinate, m (math/ray_spawn.h)
    Vec3 geometric_normal;  // unit, facing the side the ray came from is NOT guaranteed
    SurfaceKind kind = SurfaceKind::Mesh;
    uint32_t object = 0;    // index into SceneDesc::yarns or SceneDesc::meshes
    uint32_t primitive = 0; // segment (first control point index) or triangle
    uint32_t curve = 0;     // yarn: curve index within its set
    uint32_t segment = 0;   // yarn: segment index within its curve
    float u = 0.0f, v = 0.0f;
    Vec3 tangent;           // yarn: unit centre-line tangent at u
    float radius = 0.0f;    // yarn: tube radius at u
};

class EmbreeScene {
public:
    // The instruction set Embree is asked for: $PURL_EMBREE_ISA (sse2, sse4.2, avx, avx2,
    // avx512; anything else is an error), else its own choice of the best one this CPU has.
    // scripts/test.sh runs the native suites once per ISA.
    static const char* requested_isa();

    // `scene` must outlive this object: its curve and vertex buffers are shared.
    explicit EmbreeScene(const SceneDesc& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    bool intersect(const Ray& ray, SurfaceHit& hit) const;
    bool occluded(Vec3 origin, Vec3 direction, float tmin, float tmax) const;

    // Bytes held by Embree's acceleration structure and primitive data (its own count).
    size_t acceleration_bytes() const { return acceleration_bytes_; }
    float scene_extent() const { return extent_; }  // bounding-box diagonal, m

private:
    struct GeometryRef {
        SurfaceKind kind;
        uint32_t object;
    };
    const SceneDesc& scene_;
    RTCDevice device_ = nullptr;
    RTCScene rtc_scene_ = nullptr;
    std::vector<GeometryRef> geometries_;                 // by Embree geometry id
    size_t acceleration_bytes_ = 0;
    float extent_ = 1.0f;
};

}  // namespace purl
