// The denoiser's guides (Cycles' Denoising Albedo and Denoising Normal passes): the albedo and
// shading normal where a camera path first scatters non-specularly. OIDN and Blender's Denoise
// node use them to tell texture and geometry from noise.
//
// "Non-specular" follows Cycles: a lobe whose GGX alpha is below 0.075 is a mirror for this
// purpose; a hit whose mirror lobes take more than 3/4 of its albedo passes the features on to
// the next hit, tinted by those lobes' albedo. With the shipped materials every yarn hit is
// non-specular (the BYSDF's smallest alpha is 0.2 in every preset), so the features are those
// of the first hit; docs/denoising.md.
#pragma once
#include "math/vec.h"
#include "render/camera.h"
#include "render/shading.h"

namespace purl {

constexpr float kSharpAlpha = 0.075f;  // Cycles' roughness threshold for "specular" closures

// The albedo of a shading point toward wo_world (per channel, in [0, 1]) and the part of it
// carried by mirror-like lobes.
struct DenoisingAlbedo {
    Vec3 total, sharp;
};
DenoisingAlbedo denoising_albedo(const ShadingPoint& sp, Vec3 wo_world);

// One camera sample's features, fed every scattering event in path order.
class DenoisingPath {
public:
    // Records the hit unless the features are already written; holdouts write zero.
    void record(const ShadingPoint& sp, Vec3 wo_world, const Camera& camera);
    bool done() const { return done_; }
    Vec3 albedo() const { return albedo_; }
    Vec3 normal() const { return normal_; }  // camera space, unit length (0 when none)

private:
    bool done_ = false;
    Vec3 throughput_{1.0f};  // product of the mirror albedos passed so far
    Vec3 albedo_, normal_;
};

}  // namespace purl
