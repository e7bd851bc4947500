// Fresnel reflectance of a smooth dielectric interface (unpolarised light) and Schlick's fit.
#pragma once
#include "math/vec.h"

namespace purl {

// Reflectance for light arriving at cos_i (> 0: from the outside, whose index is 1) on a
// medium of relative index eta (inside / outside). Total internal reflection gives 1.
inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0) {  // arriving from the inside: swap the media
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// Schlick's approximation with reflectance f0 at normal incidence.
inline float fresnel_schlick(float f0, float cos_i) {
    const float m = clamp(1.0f - std::fabs(cos_i), 0.0f, 1.0f);
    const float m2 = m * m;
    return f0 + (1.0f - f0) * m2 * m2 * m;
}

}  // namespace purl
