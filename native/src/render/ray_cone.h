// A path's ray cone (Amanatides 1984; Akenine-Moller et al. 2021, as game and production
// renderers track it for texture filtering): the width of the bundle of rays one pixel sends,
// where it meets a surface. It tells a bounce hit how much of a yarn its light averages over,
// so the shader models no more detail than that (SurfaceShader::shade). Curved surfaces spread
// the cone: a bundle w wide reflected off a cylinder of radius R leaves 2 w / R wider in angle.
// Rough lobes spread it more; leaving that out keeps the cone narrow, so the estimate errs
// towards more detail.
#pragma once
#include <algorithm>

#include "math/ray.h"

namespace purl {

struct RayCone {
    float width = 0;   // m, at the ray's origin
    float spread = 0;  // rad, full angle

    // The camera ray's: one pixel's angle, from its differentials (0 without them).
    static RayCone from_camera(const Ray& ray) {
        RayCone cone;
        if (ray.has_differentials)
            cone.spread = std::max(length(ray.rx_direction - ray.direction), length(ray.ry_direction - ray.direction));
        return cone;
    }
    float width_at(float distance) const { return width + spread * distance; }
    // Scattered `distance` from the ray's origin, on a surface of `curvature` (1/m) across.
    void scatter(float distance, float curvature) {
        width = width_at(distance);
        spread += 2 * width * curvature;
    }
};

}  // namespace purl
