// The yarn tube around a centre-line: closest centre-line point of a point, and the chord a
// ray travels inside the tube (the BYSDF's |x - y| and the pass-through distance).
#pragma once
#include <cstdint>

#include "yarn/curve_frames.h"

namespace purl {

struct CentrelineProjection {
    uint32_t segment = 0;
    float t = 0;
    CurvePoint point;    // centre-line point with its frame (from CurveFrames::evaluate)
    float distance = 0;  // from the centre-line, m
    bool converged = false;
};

// Closest centre-line point to x by Newton steps from (segment, t); `t` may come from
// Embree's curve parameter. Stops after max_steps.
CentrelineProjection project_to_centreline(const CurveFrames& frames, Vec3 x, uint32_t segment, float t,
                                           int max_steps = 8);
// The same through a query's cache of segment expansions (the same numbers; the segments it
// expands are then at hand for the query's later evaluations), without the frame: `point` is
// the centre-line point the last Newton step already evaluated (its normal, binormal and arc
// length are left zero), which saves one evaluation.
CentrelineProjection project_to_centreline_unframed(const CachedCurve& frames, Vec3 x, uint32_t segment, float t,
                                                    int max_steps = 8);

// Distance (m) from `point`, inside or on the tube, along unit `direction` to where the ray
// leaves the tube. (segment, t) is a centre-line parameter near `point`. Exact for a straight
// tube; on bends a safeguarded root search finds the first exit. Never NaN; 0 when the ray
// leaves at once.
float tube_chord_length(const CurveFrames& frames, uint32_t segment, float t, Vec3 point, Vec3 direction);

// The same, with the centre-line parameter closest to the exit point.
struct TubeExit {
    float distance = 0;  // m
    uint32_t segment = 0;
    float t = 0;
};
TubeExit tube_exit(const CurveFrames& frames, uint32_t segment, float t, Vec3 point, Vec3 direction);
// The same from a projection of `point` onto the centre-line already at hand (project_to_centreline
// of `point`; when converged, the exit search starts from it without projecting again).
TubeExit tube_exit(const CurveFrames& frames, const CentrelineProjection& start, Vec3 point, Vec3 direction);
// The same through a query's cache of segment expansions (the same numbers; the segments the
// query has expanded already are not expanded again).
TubeExit tube_exit(const CachedCurve& frames, const CentrelineProjection& start, Vec3 point, Vec3 direction);

}  // namespace purl
