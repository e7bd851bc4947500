// Export of the explicit references' geometry, so other renderers (Cycles, for the benchmark)
// trace exactly the same plies and fibers: one "BS" BCC file (uniform cubic B-spline, Z-up,
// scene units; scene/bcc.h) and a radius side file with one little-endian float32 per control
// point in the BCC file's order (closed curves without their wrapped points), in scene units.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace purl {

// The explicit curves of every yarn set with material "ply" or "fiber", back to back, in world
// space (the scene's origin added back).
YarnCurves gather_explicit_curves(const SceneDesc& explicit_scene, std::vector<uint32_t>* set_of_curve = nullptr);

// Radii of `curves` in the order write_bcc writes their points.
std::vector<float> bcc_point_radii(const YarnCurves& curves);

struct ExplicitExport {
    size_t curves = 0, points = 0;  // as written to the BCC file
};

// Writes gather_explicit_curves(explicit_scene) to `bcc_path` and its radii to `radii_path`.
// Throws InputError when there is nothing explicit to write or a file cannot be written.
ExplicitExport write_explicit_curves(const SceneDesc& explicit_scene, const std::string& bcc_path,
                                     const std::string& radii_path);

}  // namespace purl
