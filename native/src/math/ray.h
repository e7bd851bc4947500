// Rays with optional differentials (offset rays one pixel over in x and y).
#pragma once
#include "math/vec.h"

namespace purl {

struct Ray {
    Vec3 origin, direction;  // direction is unit length
    float tmin = 0.0f, tmax = 1e30f;
    bool has_differentials = false;
    Vec3 rx_origin, rx_direction, ry_origin, ry_direction;

    Vec3 at(float t) const { return origin + direction * t; }
};

}  // namespace purl
