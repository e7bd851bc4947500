#include "render/footprint.h"

#include <cmath>
#include <limits>

#include "math/frame.h"

namespace purl {
namespace {

// Sine of the angle between ray and yarn below which the azimuthal plane has no ray in it:
// 1e-3 is 0.057 degrees; the offsets of neighbouring rays would be 1000 radii apart along the yarn.
constexpr float kMinSinAlongYarn = 1e-3f;

}  // namespace

float line_offset(Vec3 origin, Vec3 direction, const CurvePoint& axis, Vec3 across) {
    const Vec3 t = normalize(axis.tangent);
    const Vec3 toward = cross(across, t);  // silhouette-plane normal, the ray's azimuthal direction
    const float radius = std::max(axis.radius, 1e-30f);
    const float speed = dot(direction, toward);
    if (!(std::fabs(speed) > 1e-6f * length(direction))) return std::numeric_limits<float>::quiet_NaN();
    const Vec3 q = origin + direction * (dot(axis.position - origin, toward) / speed);
    return dot(q - axis.position, across) / radius;
}

AzimuthalFootprint yarn_footprint(const Ray& ray, Vec3 hit_point, const CurvePoint& axis, float scale) {
    AzimuthalFootprint f;
    const Vec3 t = normalize(axis.tangent);
    const Vec3 d = normalize(ray.direction);
    const Vec3 d_perp = d - t * dot(d, t);
    const float sin_yarn = length(d_perp);
    if (!(sin_yarn >= kMinSinAlongYarn) || !is_finite(t)) {
        // Along the yarn: no azimuthal plane holds the ray. Orient `across` by the hit anyway.
        f.along_yarn = true;
        Vec3 radial = hit_point - axis.position;
        radial = radial - t * dot(radial, t);
        Vec3 s, b;
        orthonormal_basis(is_finite(t) ? t : Vec3(0, 0, 1), s, b);
        f.across = length(radial) > 1e-6f * std::max(axis.radius, 1e-30f) ? normalize(radial) : s;
        return f;
    }
    f.across = cross(t, d_perp / sin_yarn);
    const float radius = std::max(axis.radius, 1e-30f);
    f.h0 = clamp(dot(ray.origin - axis.position, f.across) / radius, -1.0f, 1.0f);
    f.h1 = f.h2 = f.h0;
    if (!ray.has_differentials || !(scale > 0)) return f;

    const float hx = line_offset(ray.rx_origin, ray.rx_direction, axis, f.across);
    const float hy = line_offset(ray.ry_origin, ray.ry_direction, axis, f.across);
    // Unclamped h0 so a footprint is not shifted when the main ray grazes a silhouette.
    const float h_main = dot(ray.origin - axis.position, f.across) / radius;
    const float width = scale * (std::fabs(hx - h_main) + std::fabs(hy - h_main));
    if (!std::isfinite(width)) return f;  // a differential parallel to the silhouette plane
    f.valid = true;
    f.raw_width = width;
    f.h1 = clamp(f.h0 - 0.5f * width, -1.0f, 1.0f);
    f.h2 = clamp(f.h0 + 0.5f * width, -1.0f, 1.0f);
    return f;
}

}  // namespace purl
