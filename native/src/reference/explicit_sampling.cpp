#include "reference/explicit_sampling.h"

#include <algorithm>
#include <cmath>

#include "reference/spline_fit.h"
#include "yarn/ply_helix.h"

namespace purl {
namespace {

// What bounds |P''''| along one yarn curve.
struct PathScales {
    float radius = 0;     // largest yarn radius on the curve, m
    float curvature = 0;  // the centre-line curvature planned for, 1/m
    YarnTwist twist;
};

// The curvature that `quantile` of the curve's length stays below. Real yarn data (the glove)
// has a few kinks and folds tighter than the yarn radius; beyond curvature 1/R the tube folds
// onto itself and no smooth curve follows the helix there, so the plan never asks for more.
PathScales path_scales(const CurveFrames& frames, const YarnDescription& d, float quantile) {
    PathScales p;
    p.twist = yarn_twist(frames, d);
    std::vector<std::pair<float, float>> bends;  // (curvature, length it stands for)
    float total = 0;
    constexpr int kPerSegment = 4;
    for (uint32_t k = 0; k < frames.segment_count(); ++k)
        for (int i = 0; i <= kPerSegment; ++i) {
            const CurvePoint c = frames.evaluate_centreline(k, float(i) / kPerSegment);
            const float weight = (i == 0 || i == kPerSegment ? 0.5f : 1.0f) * c.speed / kPerSegment;
            p.radius = std::max(p.radius, c.radius);
            bends.emplace_back(length(c.curvature), weight);
            total += weight;
        }
    std::sort(bends.begin(), bends.end());
    float below = 0;
    for (const auto& [curvature, weight] : bends) {
        p.curvature = curvature;
        below += weight;
        if (below >= quantile * total) break;
    }
    p.curvature = std::min(p.curvature, 1.0f / std::max(p.radius, 1e-30f));
    return p;
}

// Knots for a path with |P''''| <= fourth, kept within `tolerance` (m) between knots.
CurveSampling plan(const CurveFrames& frames, double fourth, double tolerance, float radius) {
    double step = fourth > 0 ? std::pow(384 * tolerance / (5 * fourth), 0.25) : 1e30;
    // A straight, untwisted path needs no knots in between; two yarn radii keep shading smooth.
    step = std::min(step, 2.0 * radius);
    const double length = frames.total_length();
    CurveSampling s;
    s.closed = frames.closed();
    const double intervals = std::max(1.0, std::ceil(length / std::max(step, 1e-6 * radius)));
    s.knots = static_cast<uint32_t>(std::max(4.0, s.closed ? intervals : intervals + 1));
    s.step = static_cast<float>(length / (s.closed ? s.knots : s.knots - 1));
    return s;
}

}  // namespace

std::vector<float> sample_arc_lengths(const CurveSampling& plan, float length) {
    std::vector<float> s(plan.knots);
    for (uint32_t j = 0; j < plan.knots; ++j) s[j] = plan.step * float(j);
    if (!plan.closed) {
        s.back() = length;
        for (float k : {0.5f, 1.5f}) s.push_back(k * plan.step);
        for (float k : {0.5f, 1.5f}) s.push_back(length - k * plan.step);
    }
    return s;
}

std::vector<Vec4> fit_samples(const CurveSampling& plan, const std::vector<Point4d>& all) {
    const std::vector<Point4d> knots(all.begin(), all.begin() + plan.knots);
    if (plan.closed) return interpolate_closed(knots);
    const size_t n = plan.knots, x = plan.knots;  // extras: start +1/2, +3/2, end -1/2, -3/2
    const Point4d start = end_slope(all[0], all[x], all[1], all[x + 1], all[2]);
    Point4d end = end_slope(all[n - 1], all[x + 2], all[n - 2], all[x + 3], all[n - 3]);
    for (double& v : end.v) v = -v;
    return interpolate_open(knots, &start, &end);
}

CurveSampling plan_ply_sampling(const CurveFrames& frames, const YarnDescription& d, const ExplicitOptions& o) {
    const PathScales p = path_scales(frames, d, o.curvature_quantile);
    // The ply centre circles the centre-line (radius a, rate omega) while the centre-line bends.
    const double a = d.ply_distance * p.radius, omega = std::fabs(p.twist.ply_rate), kappa = p.curvature;
    const double fourth = a * std::pow(omega + kappa, 4) + std::pow(kappa, 3);
    return plan(frames, fourth, o.ply_tolerance * d.ply_radius * p.radius, p.radius);
}

CurveSampling plan_fiber_sampling(const CurveFrames& frames, const YarnDescription& d, const ExplicitOptions& o) {
    const PathScales p = path_scales(frames, d, o.curvature_quantile);
    const double a_ply = d.ply_distance * p.radius, a_fiber = d.ply_radius * p.radius;
    const double omega_ply = std::fabs(p.twist.ply_rate), kappa = p.curvature;
    // Fiber turn and migration, per metre of yarn (the twist rates are per metre of ply).
    const double omega_fiber = std::fabs(p.twist.fiber_rate) * p.twist.ply_stretch;
    const double migration = 0.5 * (d.migration_rho_max - d.migration_rho_min) * a_fiber;
    const double omega_migration = d.migration_frequency * omega_fiber;
    const double fourth = a_ply * std::pow(omega_ply + kappa, 4) +
                          a_fiber * std::pow(omega_ply + omega_fiber + kappa, 4) +
                          migration * std::pow(omega_migration, 4) + std::pow(kappa, 3);
    return plan(frames, fourth, o.fiber_tolerance * d.fiber_radius * d.ply_radius * p.radius, p.radius);
}

}  // namespace purl
