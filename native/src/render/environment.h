// The world background: constant colour, or a lat-long image importance-sampled by
// luminance, with Blender's equirectangular orientation.
#pragma once
#include <vector>

#include "math/sampling.h"
#include "scene/scene.h"

namespace purl {

class EnvironmentMap {
public:
    explicit EnvironmentMap(const WorldDesc& world);

    bool emits() const { return emits_; }
    Vec3 radiance(Vec3 direction) const;
    Vec3 sample(Vec2 u, float& pdf) const;  // solid-angle pdf
    float pdf(Vec3 direction) const;

private:
    Vec2 direction_to_uv(Vec3 d) const;  // u right, v down from the top row
    Vec3 uv_to_direction(Vec2 uv) const;

    Vec3 scale_;
    float cos_rot_ = 1, sin_rot_ = 0;
    int width_ = 0, height_ = 0;
    std::vector<Vec3> pixels_;  // rows top to bottom
    Distribution2D distribution_;
    bool emits_ = false;
};

}  // namespace purl
