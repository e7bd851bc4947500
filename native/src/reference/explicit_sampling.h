// How densely an explicit ply or fiber is sampled along its yarn. Every explicit curve is a
// uniform cubic B-spline through exact samples of its path (spline_fit.h) taken at even steps of
// yarn arc length; the step is chosen from the cubic-spline error bound 5/384 h^4 max|P''''|,
// with |P''''| bounded by the helices the path is made of (ply turn, fiber turn, migration and
// the centre-line's own bending, see ExplicitOptions), so the curve
// stays within a tolerance of its path between samples. At the samples it is exact to float
// precision.
#pragma once
#include <cstdint>
#include <vector>

#include "reference/spline_fit.h"
#include "scene/explicit_options.h"
#include "scene/curves.h"
#include "scene/yarn_set_frames.h"
#include "yarn/curve_frames.h"
#include "yarn/yarn_description.h"

namespace purl {

// Knots of the explicit curves of one yarn curve: at arc lengths j * step, j = 0 .. knots-1.
struct CurveSampling {
    uint32_t knots = 0;
    float step = 0;  // m of yarn arc length between knots
    bool closed = false;
    uint32_t control_points() const { return closed ? knots + 3 : knots + 2; }  // as YarnCurves stores them
    uint32_t segments() const { return closed ? knots : knots - 1; }
};

// Where a curve's path is sampled: the knots, then (open curves) four more at 1/2 and 3/2 knot
// steps from each end, which give the end slopes. The last knot of an open curve is its end.
std::vector<float> sample_arc_lengths(const CurveSampling& plan, float length);

// Control points through samples taken at sample_arc_lengths(plan, ...), for YarnCurves::add_curve.
std::vector<Vec4> fit_samples(const CurveSampling& plan, const std::vector<Point4d>& samples);

// Knot spacing for the plies or the fibers of one yarn curve (tolerances from `options`).
CurveSampling plan_ply_sampling(const CurveFrames& frames, const YarnDescription& d, const ExplicitOptions& options);
CurveSampling plan_fiber_sampling(const CurveFrames& frames, const YarnDescription& d, const ExplicitOptions& options);

}  // namespace purl
