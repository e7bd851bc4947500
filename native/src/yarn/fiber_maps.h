// 1D maps around the ply and the yarn (Khattar et al. 2024, sections 3.4 and 4.1), built once
// per yarn description and shared read-only by all threads.
//
// Fiber maps, around the ply circumference: for each angle a 2D ray from outside the ply toward
// its centre meets the first fiber of a procedural cross-section (ply_cross_section.h); the map
// keeps the signed angle from the ply normal to that fiber's normal, where that fiber sits
// (angle and distance from the ply centre, for its tangent tilt), and its 2D ambient
// occlusion by the other fibers, normalised over all maps to G_f = 1 - occlusion / max.
// Migration: `variants` maps of the same fibers at evenly spaced points of their migration
// cycle; along a ply, cells of fixed length each pick a variant by hash and blend smoothly
// into the next cell's, so fibers sink and surface without seams or flicker.
//
// Ply-shadowing map G_p, around the yarn circumference (relative to ply 0): the same 2D
// occlusion at the outermost ply point along each inward ray, with the plies of the
// description as occluders (no fibers), normalised the same way.
//
// The renderer's floors (BysdfParams::ply_shadow_floor, fiber_shadow_floor) are applied by
// the BYSDF, not here. Storage is 16-bit fixed point: 8 bytes per fiber-map sample.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "yarn/yarn_description.h"

namespace purl {

struct FiberSample {
    float normal_angle = 0;    // rad, rotation of the fiber normal from the ply normal about the ply tangent
    float fiber_phase = 0;     // rad, angle of the visible fiber's centre around the ply (map frame)
    float fiber_distance = 0;  // ply radii, distance of its centre from the ply centre
    float shadowing = 1;       // G_f in [0, 1]
};

class FiberMaps {
public:
    // Throws InputError (via check_yarn_description) for an invalid description.
    explicit FiberMaps(const YarnDescription& d);

    // One variant at ply angle `angle` (rad, any value; map frame), linearly interpolated.
    FiberSample sample(int variant, float angle) const;
    // Migration blend at `cell_position` (cells along the ply; see YarnTwist::migration_cell)
    // for the ply identified by `key`; loops pass their cell count so the seam matches.
    FiberSample lookup(float angle, float cell_position, uint32_t key, uint32_t cells_per_loop = 0) const;
    // The variant a cell shows (exposed for tests).
    int variant_of(uint32_t key, int64_t cell) const;

    // G_p at `azimuth` (rad) around the yarn, measured from ply 0's centre.
    float ply_shadowing(float azimuth) const;
    // G_f averaged over the ply's circumference and all variants (a ply seen as a whole).
    float mean_fiber_shadowing() const { return mean_fiber_shadowing_; }

    int variants() const { return variants_; }
    int resolution() const { return resolution_; }
    size_t memory_bytes() const;

private:
    struct Packed {
        int16_t normal_angle;   // pi / 32767 rad per step
        uint16_t fiber_phase;   // 2 pi / 65536 rad per step
        uint16_t fiber_distance;  // 1 / 32768 ply radii per step
        uint16_t shadowing;     // 1 / 65535 per step
    };
    FiberSample unpack(const Packed& p) const;
    FiberSample sample_pair(int a, int b, float angle, float w) const;

    int variants_ = 0, resolution_ = 0;
    float mean_fiber_shadowing_ = 1;
    std::vector<Packed> fiber_;      // variants_ x resolution_
    std::vector<uint16_t> ply_;      // resolution_
};

}  // namespace purl
