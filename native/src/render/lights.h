// Light sources with Cycles' radiometry: point/spot (sphere when they have a radius),
// sun (cone of directions), rectangle/disk area lights, constant or lat-long environment.
#pragma once
#include <memory>
#include <vector>

#include "math/ray.h"
#include "math/sampling.h"
#include "scene/scene.h"

namespace purl {

struct LightSample {
    Vec3 wi;              // unit direction from the shading point toward the light
    float distance = 0;   // to the sampled point; infinity for sun and environment
    Vec3 radiance;        // arriving radiance (delta lights: irradiance-like value, pdf = 1)
    float pdf = 0;        // solid-angle pdf including the light selection probability
    bool delta = false;
};

struct EmitterHit {
    Vec3 radiance;
    float distance = 0;
    float pdf = 0;  // solid-angle pdf of having sampled this direction by light sampling
};

class EnvironmentMap;

// One light in world space with its emission precomputed from the Blender values.
struct Emitter {
    LightType type = LightType::Point;
    Vec3 position;          // point/spot centre, area centre
    Vec3 axis;              // spot and area: emission direction; sun: direction toward the sun
    Vec3 half_u, half_v;    // area: half extents along the light's local x and y
    bool disk = false;      // area: disk or ellipse
    float area = 0;         // area: m^2
    float radius = 0;       // point/spot sphere radius
    float cos_half_spot = -1, spot_smooth = 0;
    float cos_sun = 1;      // cosine of the sun's angular radius
    Vec3 radiance;          // sphere, area and sun-disc radiance
    Vec3 delta_value;       // point: intensity (W/sr); sun without size: irradiance (W/m^2)
};

class Lights {
public:
    explicit Lights(const SceneDesc& scene);
    ~Lights();

    bool empty() const { return count_ == 0; }
    // Picks one light (uniformly) and samples a direction toward it from `p`.
    bool sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const;
    // Nearest area or sphere light along the ray before `t_max`, if any.
    bool intersect_emitter(const Ray& ray, float t_max, EmitterHit& out) const;
    // Calls f(EmitterHit) for the environment and each sun disc seen along an escaping ray.
    template <class F>
    void for_each_escaped(Vec3 direction, F&& f) const;
    // Background seen by camera rays (environment only, no sun disc), for the Combined pass.
    Vec3 background(Vec3 direction) const;

private:
    EmitterHit environment_hit(Vec3 direction) const;
    float selection_pdf() const { return 1.0f / static_cast<float>(count_); }
    bool sample_one(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const;

    std::vector<Emitter> emitters_;
    std::unique_ptr<EnvironmentMap> environment_;
    size_t count_ = 0;  // emitters plus the environment when it emits
};

template <class F>
void Lights::for_each_escaped(Vec3 direction, F&& f) const {
    if (environment_) f(environment_hit(direction));
    for (const Emitter& e : emitters_)
        if (e.type == LightType::Sun && e.cos_sun < 1 && dot(direction, e.axis) >= e.cos_sun)
            f(EmitterHit{e.radiance, 1e30f, uniform_cone_pdf(e.cos_sun) * selection_pdf()});
}

}  // namespace purl
