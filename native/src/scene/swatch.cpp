#include "scene/swatch.h"

#include <cmath>
#include <vector>

#include "base/input_error.h"
#include "math/number_text.h"
#include "math/spline_convert.h"

namespace purl {
namespace {

// Stockinette loop in units of the yarn radius R, per course with t in [0, 2 pi) per wale:
//   x = w t / 2pi + a sin 2t,  y = -b cos t,  z = -d cos 2t.
// t = 0 is the sinker (back), t = pi/2 and 3pi/2 the legs (front), t = pi the head (back).
// The sin 2t term narrows the legs at their feet (the "V"), so the legs of the course above
// cross this course's head from inside the loop: each half-loop links the loop below once.
// Courses overlap (2b > h) so feet reach under the previous head. The numbers come from a
// search maximising clearance per loop area. Measured on the generated B-splines: 2.20 R
// between courses, 2.28 R between distant parts of one course, curvature radius >= 2.5 R.
constexpr double kKnitWale = 9.5;     // w, wale spacing
constexpr double kKnitCourse = 4.8;   // h, course spacing
constexpr double kKnitNarrow = 2.3;   // a, leg narrowing
constexpr double kKnitHalfHeight = 4.0;  // b, half the loop height
constexpr double kKnitDepth = 2.4;    // d, front/back excursion
constexpr int kKnitNodesPerLoop = 16; // interpolation nodes per loop

// Weave crossings sit +-1.15 R from the mid-plane (2.3 R between centre-lines); with yarns
// 5 R apart the interpolated crimp keeps >= 2.12 R between warp and weft everywhere
// (measured: plain 2.21 R, twill 2/1 2.14 R, 2/2 2.13 R, satin 2.18 R).
constexpr double kWeaveCrimp = 1.15;
constexpr double kWeaveSpacing = 5.0;
constexpr int kSatinHarness = 5, kSatinStep = 2;  // 5-harness satin, move number 2

constexpr double kTwoPi = 6.283185307179586;

void check_count(int value, const char* name, int max_value) {
    if (value < 1 || value > max_value)
        throw InputError("swatch", name, std::string(name) + " must be between 1 and " +
                                             std::to_string(max_value) + ", got " + std::to_string(value));
}

// Bounds on a swatch's total size, so a typo cannot ask for tens of GB: a weave cell takes about
// 4 control points, at about 150 B each with Embree and frames (docs/robustness.md, scale test).
constexpr double kMaxWeaveCells = 4e6, kMaxKnitLoops = 1e6;

void check_total(double cells, double max_cells, const char* what) {
    if (cells > max_cells)
        throw InputError("swatch", what, std::string(what) + " " + std::to_string(static_cast<long long>(cells)) +
                                             " is more than the " + std::to_string(static_cast<long long>(max_cells)) +
                                             " a swatch may have");
}

YarnCurves make_knit(const SwatchOptions& opt, double radius, double spacing) {
    check_count(opt.courses, "courses", 2000);
    check_count(opt.wales, "wales", 2000);
    check_total(double(opt.courses) * opt.wales, kMaxKnitLoops, "courses x wales");
    const double unit = spacing / kKnitWale;  // m per shape unit: R at the default spacing
    const double w = kKnitWale * unit, h = kKnitCourse * unit, a = kKnitNarrow * unit;
    const double b = kKnitHalfHeight * unit, d = kKnitDepth * unit;
    const double x0 = -0.5 * opt.wales * w, y0 = -0.5 * (opt.courses - 1) * h;
    const int nodes = kKnitNodesPerLoop * opt.wales + 1;

    YarnCurves curves;
    std::vector<Vec4> path(nodes);
    for (int c = 0; c < opt.courses; ++c) {
        for (int k = 0; k < nodes; ++k) {
            const double t = kTwoPi * k / kKnitNodesPerLoop;
            path[k] = Vec4(static_cast<float>(x0 + w * t / kTwoPi + a * std::sin(2 * t)),
                           static_cast<float>(y0 + c * h - b * std::cos(t)),
                           static_cast<float>(-d * std::cos(2 * t)), static_cast<float>(radius));
        }
        const std::vector<Vec4> cps = interpolate_bspline(path.data(), path.size(), false);
        curves.add_curve(cps.data(), cps.size(), false);
    }
    return curves;
}

// Does warp `j` pass over weft `i`?
bool warp_over(SwatchKind kind, const SwatchOptions& opt, int i, int j) {
    switch (kind) {
        case SwatchKind::Plain: return (i + j) % 2 == 0;
        case SwatchKind::Twill: return (i + j) % (opt.twill_over + opt.twill_under) < opt.twill_over;
        case SwatchKind::Satin: return ((i - kSatinStep * j) % kSatinHarness + kSatinHarness) % kSatinHarness != 0;
        case SwatchKind::Knit: break;
    }
    return true;
}

// One yarn crossing `n` others at u = (k - (n-1)/2) * s, at heights `level[k]` (m). Nodes at
// the crossings, halfway between them (mean height) and half a spacing past each end.
std::vector<Vec4> weave_yarn(const std::vector<double>& level, double s, double across,
                             bool along_y, double radius) {
    const int n = static_cast<int>(level.size());
    std::vector<Vec4> nodes;
    nodes.reserve(2 * n + 1);
    auto add = [&](double u, double z) {
        const float uf = static_cast<float>(u), af = static_cast<float>(across);
        nodes.emplace_back(along_y ? af : uf, along_y ? uf : af, static_cast<float>(z),
                           static_cast<float>(radius));
    };
    const double u0 = -0.5 * (n - 1) * s;
    add(u0 - 0.5 * s, 0.5 * level[0]);
    for (int k = 0; k < n; ++k) {
        add(u0 + k * s, level[k]);
        if (k + 1 < n) add(u0 + (k + 0.5) * s, 0.5 * (level[k] + level[k + 1]));
    }
    add(u0 + (n - 0.5) * s, 0.5 * level[n - 1]);
    return interpolate_bspline(nodes.data(), nodes.size(), false);
}

YarnCurves make_weave(SwatchKind kind, const SwatchOptions& opt, double radius, double s) {
    check_count(opt.warps, "warps", 5000);
    check_count(opt.wefts, "wefts", 5000);
    check_total(double(opt.warps) * opt.wefts, kMaxWeaveCells, "warps x wefts");
    if (kind == SwatchKind::Twill) {
        check_count(opt.twill_over, "twill_over", 16);
        check_count(opt.twill_under, "twill_under", 16);
    }
    const double crimp = kWeaveCrimp * radius;
    YarnCurves curves;
    std::vector<double> level;
    // Warps (along Y) first, then wefts (along X); a weft is low wherever the warp is high.
    for (int j = 0; j < opt.warps; ++j) {
        level.assign(opt.wefts, 0.0);
        for (int i = 0; i < opt.wefts; ++i) level[i] = warp_over(kind, opt, i, j) ? crimp : -crimp;
        const std::vector<Vec4> cps = weave_yarn(level, s, (j - 0.5 * (opt.warps - 1)) * s, true, radius);
        curves.add_curve(cps.data(), cps.size(), false);
    }
    for (int i = 0; i < opt.wefts; ++i) {
        level.assign(opt.warps, 0.0);
        for (int j = 0; j < opt.warps; ++j) level[j] = warp_over(kind, opt, i, j) ? -crimp : crimp;
        const std::vector<Vec4> cps = weave_yarn(level, s, (i - 0.5 * (opt.wefts - 1)) * s, false, radius);
        curves.add_curve(cps.data(), cps.size(), false);
    }
    return curves;
}

}  // namespace

float default_swatch_spacing(SwatchKind kind, float yarn_radius) {
    return static_cast<float>((kind == SwatchKind::Knit ? kKnitWale : kWeaveSpacing) * yarn_radius);
}

YarnCurves generate_swatch(SwatchKind kind, const SwatchOptions& opt) {
    const double radius = opt.yarn_radius;
    if (!(radius > 0) || !std::isfinite(radius) || radius > 1.0)
        throw InputError("swatch", "yarn_radius", "yarn radius must be in (0, 1] m, got " + number_text(radius));
    const double minimum = default_swatch_spacing(kind, opt.yarn_radius);
    double spacing = opt.spacing;
    if (spacing == 0) spacing = minimum;
    if (!std::isfinite(spacing) || spacing < minimum * (1 - 1e-6) || spacing > 1000 * minimum)
        throw InputError("swatch", "spacing",
                         "spacing " + number_text(opt.spacing) + " m is outside [" + number_text(minimum) +
                             ", " + number_text(1000 * minimum) + "] m for yarn radius " +
                             number_text(radius) + " m (tighter yarns would intersect); use 0 for the default");
    return kind == SwatchKind::Knit ? make_knit(opt, radius, spacing) : make_weave(kind, opt, radius, spacing);
}

SwatchKind parse_swatch_kind(const std::string& name) {
    if (name == "knit") return SwatchKind::Knit;
    if (name == "plain") return SwatchKind::Plain;
    if (name == "twill") return SwatchKind::Twill;
    if (name == "satin") return SwatchKind::Satin;
    throw InputError("swatch", "kind", "unknown swatch kind '" + name + "'; expected knit, plain, twill or satin");
}

}  // namespace purl
