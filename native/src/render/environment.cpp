#include "render/environment.h"

#include <cmath>

#include "io/image_io.h"

namespace purl {

EnvironmentMap::EnvironmentMap(const WorldDesc& world) {
    scale_ = world.color * world.strength;
    cos_rot_ = std::cos(world.rotation_z);
    sin_rot_ = std::sin(world.rotation_z);
    if (world.texture.empty()) {
        emits_ = max_component(scale_) > 0;
        return;
    }
    const ImageRGB image = read_image_rgb(world.texture);
    width_ = image.width;
    height_ = image.height;
    pixels_.resize(size_t(width_) * height_);
    std::vector<float> weights(pixels_.size());
    for (int y = 0; y < height_; ++y) {
        // Rows near the poles cover less solid angle.
        const float sin_theta = std::sin(kPi * (y + 0.5f) / height_);
        for (int x = 0; x < width_; ++x) {
            const size_t i = size_t(y) * width_ + x;
            const float* rgb = &image.rgb[3 * i];
            pixels_[i] = Vec3(std::max(0.0f, rgb[0]), std::max(0.0f, rgb[1]), std::max(0.0f, rgb[2]));
            weights[i] = luminance(pixels_[i] * scale_) * sin_theta;
        }
    }
    distribution_ = Distribution2D(weights.data(), width_, height_);
    emits_ = max_component(scale_) > 0;
}

// Cycles' equirectangular mapping: u = 0.5 - atan2(y, x) / 2pi, top row at +Z.
Vec2 EnvironmentMap::direction_to_uv(Vec3 d) const {
    const Vec3 t(cos_rot_ * d.x + sin_rot_ * d.y, -sin_rot_ * d.x + cos_rot_ * d.y, d.z);
    float u = 0.5f - std::atan2(t.y, t.x) / (2 * kPi);
    u -= std::floor(u);
    const float v = std::acos(clamp(t.z, -1.0f, 1.0f)) / kPi;
    return {std::min(u, 0.99999994f), std::min(v, 0.99999994f)};
}

Vec3 EnvironmentMap::uv_to_direction(Vec2 uv) const {
    const float phi = kPi * (1 - 2 * uv.x), theta = kPi * uv.y;
    const Vec3 t(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    return {cos_rot_ * t.x - sin_rot_ * t.y, sin_rot_ * t.x + cos_rot_ * t.y, t.z};
}

Vec3 EnvironmentMap::radiance(Vec3 direction) const {
    if (pixels_.empty()) return scale_;
    const Vec2 uv = direction_to_uv(direction);
    const int x = std::min(int(uv.x * width_), width_ - 1), y = std::min(int(uv.y * height_), height_ - 1);
    return pixels_[size_t(y) * width_ + x] * scale_;
}

Vec3 EnvironmentMap::sample(Vec2 u, float& pdf) const {
    if (pixels_.empty()) {
        pdf = uniform_sphere_pdf();
        return sample_uniform_sphere(u);
    }
    float pdf_uv;
    const Vec2 uv = distribution_.sample(u, pdf_uv);
    const float sin_theta = std::sin(kPi * uv.y);
    pdf = sin_theta > 0 ? pdf_uv / (2 * kPi * kPi * sin_theta) : 0.0f;
    return uv_to_direction(uv);
}

float EnvironmentMap::pdf(Vec3 direction) const {
    if (pixels_.empty()) return uniform_sphere_pdf();
    const Vec2 uv = direction_to_uv(direction);
    const float sin_theta = std::sin(kPi * uv.y);
    return sin_theta > 0 ? distribution_.pdf(uv) / (2 * kPi * kPi * sin_theta) : 0.0f;
}

}  // namespace purl
