// The yarn radius a curve file implies: BCC and simulation exports carry centre-lines only,
// and neighbouring yarns lie about two radii apart.
#pragma once
#include "scene/curves.h"

namespace purl {

struct YarnSpacing {
    float radius = 0;         // half the median distance to the nearest other yarn; 0 when none was found
    size_t samples = 0;       // points sampled along the centre-lines
    float found_share = 0;    // share of them that had another yarn within the search radius
};

// Samples every segment at 4 points and, for each sample, finds the nearest sample of another
// yarn: another curve, or the same curve after it has turned back on itself (arc length between
// the two more than pi times their distance). Uniform-grid search, doubling its cell until
// most samples see a neighbour. Positions only: the curves' radii are ignored.
YarnSpacing estimate_yarn_spacing(const YarnCurves& curves);

}  // namespace purl
