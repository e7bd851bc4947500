// The explicit references, built from the same yarn curves and description as the BYSDF:
// every ply as its own curve (Montazeri et al. 2020), or every fiber as its own curve
// (Khungurn et al. 2015 / Zhao et al. 2016), for ground truth and comparisons.
#pragma once
#include "scene/scene.h"

namespace purl {

// A copy of `scene` whose BYSDF yarn sets are replaced by explicit ply or fiber curves with
// their own materials, for `model` Ply or Fiber. Throws InputError when the result would
// not fit in memory.
SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model);

}  // namespace purl
