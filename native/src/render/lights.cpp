#include "render/lights.h"

#include <cmath>

#include "math/frame.h"
#include "render/environment.h"

namespace purl {

namespace {

float smoothstep01(float x) {
    x = clamp(x, 0.0f, 1.0f);
    return x * x * (3 - 2 * x);
}

// Cycles' spot cone: zero outside spot_size / 2, smoothstep over the blend region.
float spot_factor(const Emitter& e, Vec3 light_to_point) {
    if (e.type != LightType::Spot) return 1.0f;
    const float c = dot(light_to_point, e.axis);
    if (c <= e.cos_half_spot) return 0.0f;
    return e.spot_smooth > 0 ? smoothstep01((c - e.cos_half_spot) / e.spot_smooth) : 1.0f;
}

// Nearest positive hit of a ray with a sphere; -1 when none.
float ray_sphere(Vec3 o, Vec3 d, Vec3 c, float r) {
    const Vec3 oc = o - c;
    const float b = dot(oc, d), cc = dot(oc, oc) - r * r;
    const float disc = b * b - cc;
    if (disc < 0) return -1;
    const float s = std::sqrt(disc);
    const float t0 = -b - s, t1 = -b + s;
    return t0 > 0 ? t0 : (t1 > 0 ? t1 : -1);
}

Emitter make_emitter(const LightDesc& l) {
    Emitter e;
    e.type = l.type;
    e.position = l.to_world.translation();
    const Vec3 z = l.to_world.column(2);
    switch (l.type) {
        case LightType::Point:
        case LightType::Spot: {
            const Vec3 intensity = l.color * (l.power * kInv4Pi);  // W/sr
            e.axis = normalize(-z);
            e.radius = l.radius * l.to_world.uniform_scale();
            e.delta_value = intensity;
            if (e.radius > 0) e.radiance = intensity / (kPi * e.radius * e.radius);
            e.cos_half_spot = std::cos(0.5f * l.spot_size);
            e.spot_smooth = (1 - e.cos_half_spot) * l.spot_blend;
            break;
        }
        case LightType::Sun: {
            e.axis = normalize(z);  // the sun shines along -Z, so it is seen toward +Z
            const float half = 0.5f * l.angle;
            e.cos_sun = half > 0 ? std::cos(half) : 1.0f;
            const Vec3 irradiance = l.color * l.strength;
            e.delta_value = irradiance;
            if (half > 0) e.radiance = irradiance / (kPi * sqr(std::sin(half)));
            break;
        }
        case LightType::Area: {
            e.axis = normalize(-z);
            e.half_u = l.to_world.column(0) * (0.5f * l.size);
            e.half_v = l.to_world.column(1) * (0.5f * l.size_y);
            e.disk = l.shape == AreaShape::Disk || l.shape == AreaShape::Ellipse;
            const float full = 4 * length(e.half_u) * length(e.half_v);
            e.area = e.disk ? full * kPi / 4 : full;
            e.radiance = l.color * (0.25f * l.power / e.area);
            break;
        }
    }
    return e;
}

// Ray against an area light's plane and shape; -1 when missed or from behind.
float ray_area(const Emitter& e, Vec3 o, Vec3 d) {
    const float denom = dot(d, e.axis);
    if (denom >= 0) return -1;  // one-sided: light leaves along axis
    const float t = dot(e.position - o, e.axis) / denom;
    if (t <= 0) return -1;
    const Vec3 q = o + d * t - e.position;
    const float a = dot(q, e.half_u) / length_squared(e.half_u);
    const float b = dot(q, e.half_v) / length_squared(e.half_v);
    const bool inside = e.disk ? a * a + b * b <= 1 : (std::fabs(a) <= 1 && std::fabs(b) <= 1);
    return inside ? t : -1;
}

}  // namespace

Lights::Lights(const SceneDesc& scene) {
    for (const LightDesc& l : scene.lights) {
        const float power = l.type == LightType::Sun ? l.strength : l.power;
        if (power > 0 && max_component(l.color) > 0) emitters_.push_back(make_emitter(l));
    }
    environment_ = std::make_unique<EnvironmentMap>(scene.world);
    if (!environment_->emits()) environment_.reset();
    count_ = emitters_.size() + (environment_ ? 1 : 0);
}

Lights::~Lights() = default;

bool Lights::sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const {
    if (count_ == 0) return false;
    const size_t index = std::min(static_cast<size_t>(u_select * count_), count_ - 1);
    if (index == emitters_.size()) {
        float pdf;
        out.wi = environment_->sample(u, pdf);
        out.radiance = environment_->radiance(out.wi);
        out.pdf = pdf * selection_pdf();
        out.distance = 1e30f;
        out.delta = false;
        return pdf > 0;
    }
    if (!sample_one(emitters_[index], p, u, out)) return false;
    out.pdf *= selection_pdf();
    return true;
}

bool Lights::sample_one(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const {
    switch (e.type) {
        case LightType::Point:
        case LightType::Spot: {
            const Vec3 to_centre = e.position - p;
            const float d2 = length_squared(to_centre), d = std::sqrt(d2);
            if (!(d > e.radius)) return false;
            const Vec3 w = to_centre / d;
            if (e.radius == 0) {
                out.wi = w;
                out.distance = d;
                out.radiance = e.delta_value * (spot_factor(e, -w) / d2);
                out.pdf = 1;
                out.delta = true;
                return true;
            }
            const float cos_max = safe_sqrt(1 - e.radius * e.radius / d2);
            out.wi = Frame::from_normal(w).to_world(sample_uniform_cone(u, cos_max));
            const float t = ray_sphere(p, out.wi, e.position, e.radius);
            out.distance = t > 0 ? t : d - e.radius;
            // As Cycles 4.x: the cone is evaluated along the ray (light toward the shading point),
            // the same function of (p, wi) as for BSDF-sampled hits below, so MIS stays consistent.
            out.radiance = e.radiance * spot_factor(e, -out.wi);
            out.pdf = uniform_cone_pdf(cos_max);
            out.delta = false;
            return true;
        }
        case LightType::Sun:
            out.distance = 1e30f;
            if (e.cos_sun >= 1) {
                out.wi = e.axis;
                out.radiance = e.delta_value;
                out.pdf = 1;
                out.delta = true;
            } else {
                out.wi = Frame::from_normal(e.axis).to_world(sample_uniform_cone(u, e.cos_sun));
                out.radiance = e.radiance;
                out.pdf = uniform_cone_pdf(e.cos_sun);
                out.delta = false;
            }
            return true;
        case LightType::Area: {
            Vec3 q;
            if (e.disk) {
                const Vec2 d = sample_uniform_disk_concentric(u);
                q = e.position + e.half_u * d.x + e.half_v * d.y;
            } else {
                q = e.position + e.half_u * (2 * u.x - 1) + e.half_v * (2 * u.y - 1);
            }
            const Vec3 to_light = q - p;
            const float d2 = length_squared(to_light), d = std::sqrt(d2);
            if (!(d > 0)) return false;
            out.wi = to_light / d;
            const float cos_light = -dot(out.wi, e.axis);
            if (cos_light <= 0) return false;
            out.distance = d;
            out.radiance = e.radiance;
            out.pdf = d2 / (e.area * cos_light);
            out.delta = false;
            return true;
        }
    }
    return false;
}

bool Lights::intersect_emitter(const Ray& ray, float t_max, EmitterHit& out) const {
    bool found = false;
    for (const Emitter& e : emitters_) {
        float t = -1;
        if (e.type == LightType::Area) {
            t = ray_area(e, ray.origin, ray.direction);
        } else if ((e.type == LightType::Point || e.type == LightType::Spot) && e.radius > 0) {
            t = ray_sphere(ray.origin, ray.direction, e.position, e.radius);
        }
        if (!(t > ray.tmin && t < t_max)) continue;
        t_max = t;
        found = true;
        out.distance = t;
        if (e.type == LightType::Area) {
            const float cos_light = -dot(ray.direction, e.axis);
            out.radiance = e.radiance;
            out.pdf = t * t / (e.area * cos_light) * selection_pdf();
        } else {
            const float d2 = length_squared(e.position - ray.origin);
            const float cos_max = safe_sqrt(1 - std::min(1.0f, e.radius * e.radius / d2));
            out.radiance = e.radiance * spot_factor(e, -ray.direction);  // not the sphere's normal
            out.pdf = uniform_cone_pdf(cos_max) * selection_pdf();
        }
    }
    return found;
}

EmitterHit Lights::environment_hit(Vec3 direction) const {
    return {environment_->radiance(direction), 1e30f, environment_->pdf(direction) * selection_pdf()};
}

Vec3 Lights::background(Vec3 direction) const {
    return environment_ ? environment_->radiance(direction) : Vec3(0.0f);
}

}  // namespace purl
