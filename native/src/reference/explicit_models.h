// The explicit references, built from the same yarn curves and description as the BYSDF:
// every ply as its own curve (Montazeri et al. 2020), or every fiber as its own curve
// (Khungurn et al. 2015 / Zhao et al. 2016), for ground truth and comparisons.
//
// Only yarn sets with material "bysdf" are converted; other sets and meshes pass unchanged.
// Ply sets get material "ply" (the BYSDF's parameters at ply level, PlyOrigins filled in);
// fiber sets get material "fiber" (the set's FiberBcsdfParams).
#pragma once
#include <cstddef>
#include <vector>

#include "reference/explicit_sampling.h"
#include "scene/scene.h"

namespace purl {

// What the explicit geometry of one yarn set will hold, computed before anything is allocated.
struct ExplicitSetSize {
    size_t curves = 0, control_points = 0, segments = 0;
    size_t bytes = 0;  // estimate: curves, Embree's structure and the shader's frames
};
struct ExplicitSize {
    std::vector<ExplicitSetSize> sets;  // per yarn set of the scene (zero for sets left alone)
    ExplicitSetSize total;
};

// Embree's round B-spline structure (BVH plus primitive data) per curve segment, measured on
// this build (Embree 3.13, build quality high): see docs/explicit-references.md.
constexpr size_t kEmbreeBytesPerSegment = 128;

ExplicitSize explicit_size(const SceneDesc& scene, YarnModel model, const ExplicitOptions& options = {});

// A copy of `scene` whose BYSDF yarn sets are replaced by explicit ply or fiber curves with
// their own materials, for `model` Ply or Fiber (Bysdf returns the scene unchanged). Throws
// InputError, before allocating the curves, when explicit_size exceeds the memory budget.
// Without options, the scene's own (render.explicit in the JSON scene).
SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model);
SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model, const ExplicitOptions& options);

}  // namespace purl
