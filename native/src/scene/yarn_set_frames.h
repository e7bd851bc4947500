// The curve frames of a yarn set: what the shader builds for every BYSDF and explicit ply set,
// and what the explicit references are built from, so the two agree on every frame, arc length
// and twist.
#pragma once
#include <vector>

#include "scene/curves.h"
#include "yarn/curve_frames.h"

namespace purl {

// One CurveFrames per curve; they point into `curves`, which must outlive them.
std::vector<CurveFrames> yarn_set_frames(const YarnCurves& curves);

}  // namespace purl
