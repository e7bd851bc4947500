// What every scattering model's `sample` returns, and the flags that describe a lobe.
#pragma once
#include <cstdint>

#include "math/vec.h"

namespace purl {

// Lobe properties. None of Purl's lobes is a delta distribution: every sample has a
// finite pdf, so multiple importance sampling always applies.
enum BsdfFlags : uint32_t {
    kBsdfReflection = 1u << 0,    // wi on the same side of the local frame as wo
    kBsdfTransmission = 1u << 1,  // wi on the opposite side
    kBsdfSpecular = 1u << 2,      // a glossy microfacet lobe (not a mirror)
    kBsdfBody = 1u << 3,          // a diffuse-like body (multiple scattering) lobe
};

struct BsdfSample {
    Vec3 wi;              // sampled direction, local frame, unit length, pointing away
    Vec3 f;               // model value at (wo, wi), without the cosine factor, 1/sr
    float pdf = 0;        // solid-angle density of the whole sampler (all lobes) at wi, 1/sr
    uint32_t flags = 0;   // BsdfFlags of the lobe that produced wi
    int lobe = 0;         // model-specific index of that lobe

    bool is_transmission() const { return (flags & kBsdfTransmission) != 0; }
    // The path-throughput factor f * |cos theta_i| / pdf.
    Vec3 weight() const { return pdf > 0 ? f * (std::fabs(wi.z) / pdf) : Vec3(0.0f); }
};

// Value and density at one pair of directions, computed together.
struct BsdfEvalPdf {
    Vec3 f;
    float pdf = 0;
};

}  // namespace purl
