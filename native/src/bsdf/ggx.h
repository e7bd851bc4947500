// Anisotropic GGX (Trowbridge-Reitz) microfacet distribution in a local frame with the
// macro normal along +z and alpha_x measured along +x (the fiber tangent for yarns).
// Smith masking; visible-normal sampling after Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals" (JCGT 7(4)).
#pragma once
#include "math/vec.h"

namespace purl {

struct Ggx {
    float alpha_x = 0.5f;  // roughness along +x (dimensionless slope scale)
    float alpha_y = 0.5f;  // roughness along +y

    // Normal distribution D(h), per steradian of microfacet normal; 0 below the surface.
    float d(Vec3 h) const {
        if (h.z <= 0) return 0.0f;
        const float sx = h.x / alpha_x, sy = h.y / alpha_y;
        const float k = sx * sx + sy * sy + h.z * h.z;
        return 1.0f / (kPi * alpha_x * alpha_y * k * k);
    }
    // Smith Lambda for direction w (either side of the surface).
    float lambda(Vec3 w) const {
        const float z2 = w.z * w.z;
        if (z2 <= 0) return 1e30f;
        const float t2 = (sqr(alpha_x * w.x) + sqr(alpha_y * w.y)) / z2;
        return 0.5f * (std::sqrt(1.0f + t2) - 1.0f);
    }
    float g1(Vec3 w) const { return 1.0f / (1.0f + lambda(w)); }
    // Uncorrelated masking-shadowing, as the paper writes it: G1(wo) G1(wi).
    float g2(Vec3 wo, Vec3 wi) const { return g1(wo) * g1(wi); }

    // Microfacet normal drawn from the distribution of normals visible from wo (wo.z > 0).
    Vec3 sample_visible_normal(Vec3 wo, Vec2 u) const {
        // Stretch to the hemisphere configuration where alpha = 1.
        const Vec3 v = normalize(Vec3(alpha_x * wo.x, alpha_y * wo.y, wo.z));
        const float len2 = v.x * v.x + v.y * v.y;
        const Vec3 t1 = len2 > 1e-14f ? Vec3(-v.y, v.x, 0) / std::sqrt(len2) : Vec3(1, 0, 0);
        const Vec3 t2 = cross(v, t1);
        // Uniform disk point, warped onto the visible half of the projected disk.
        const float r = std::sqrt(u.x), phi = 2 * kPi * u.y;
        const float p1 = r * std::cos(phi);
        const float s = 0.5f * (1.0f + v.z);
        const float p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * r * std::sin(phi);
        const Vec3 n_stretched = t1 * p1 + t2 * p2 + v * safe_sqrt(1.0f - p1 * p1 - p2 * p2);
        // Unstretch back to the ellipsoid.
        return normalize(Vec3(alpha_x * n_stretched.x, alpha_y * n_stretched.y,
                              std::max(1e-7f, n_stretched.z)));
    }
    // Density of sample_visible_normal over microfacet normals: G1(wo) max(0, wo.h) D(h) / wo.z.
    float visible_normal_pdf(Vec3 wo, Vec3 h) const {
        const float cos_o = dot(wo, h);
        if (wo.z <= 0 || cos_o <= 0) return 0.0f;
        return g1(wo) * cos_o * d(h) / wo.z;
    }
};

// Mirror direction of w about the unit normal h.
inline Vec3 reflect(Vec3 w, Vec3 h) { return h * (2 * dot(w, h)) - w; }

// Refracts w (on the side h points to, index 1) into the medium of relative index eta.
// Returns false on total internal reflection (only possible for eta < 1).
inline bool refract(Vec3 w, Vec3 h, float eta, Vec3& out) {
    const float cos_i = dot(w, h);
    const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    out = -w / eta + h * (cos_i / eta - cos_t);
    return true;
}

}  // namespace purl
