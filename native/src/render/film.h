// Per-pixel results of a render and their conversion to image passes.
#pragma once
#include <vector>

#include "io/image_io.h"
#include "math/vec.h"

namespace purl {

constexpr float kNoHitDepth = 1e10f;  // Cycles' Depth for pixels that see no surface
// Cycles' pass names, which Blender's Denoise node is meant to be fed with.
inline constexpr const char* kDenoisingAlbedoPass = "Denoising Albedo";
inline constexpr const char* kDenoisingNormalPass = "Denoising Normal";

struct PixelResult {
    Vec3 color;        // premultiplied by alpha
    float alpha = 0;
    float depth = kNoHitDepth;  // camera-axis distance of the nearest first hit
    Vec3 normal;       // mean world normal of first hits
    float yarn_id = 0; // 1 + global curve id of the first hit of sample 0; 0 when none
    // Sample 0's first scattering ply (after passing between plies): index, -1 when none (no
    // yarn, a mesh, a placeholder or fiber yarn, far-field shading); u_ply (rad) and v_ply (m
    // along the ply from the root), 0 when none.
    float ply_index = -1;
    float u_ply = 0, v_ply = 0;
    // Denoising features (render/denoising_features.h): mean albedo and camera-space normal of
    // each sample's first non-specular hit; 0 where samples saw no surface.
    Vec3 denoising_albedo, denoising_normal;
};

class Film {
public:
    Film(int width, int height) : width_(width), height_(height), pixels_(size_t(width) * height) {}
    int width() const { return width_; }
    int height() const { return height_; }
    PixelResult& at(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
    const PixelResult& at(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }

    // Combined (RGBA), Depth (Z), Normal (XYZ), YarnID (X), PlyIndex (X), PlyUV (U, V),
    // Denoising Albedo (RGB), Denoising Normal (XYZ), rows top to bottom.
    RenderImage to_image() const;

private:
    int width_, height_;
    std::vector<PixelResult> pixels_;
};

}  // namespace purl
