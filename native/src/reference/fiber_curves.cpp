#include "reference/fiber_curves.h"

#include <cmath>

#include "math/rng.h"
#include "yarn/arc_length.h"
#include "reference/spline_fit.h"
#include "yarn/ply_cross_section.h"
#include "yarn/ply_helix.h"

namespace purl {
namespace {

// A ply's cross-section frame at one knot: centre, e_1, e_2 (m, unit, unit) and ply radius (m).
struct PlyFrame {
    Vec3 centre, e1, e2;
    float radius;
};

}  // namespace

std::vector<FiberRest> ply_fiber_rest_positions(const YarnDescription& d, uint32_t curve_key, int ply) {
    Rng rng(mix64(static_cast<uint64_t>(d.seed) * 0x9e3779b97f4a7c15ULL + curve_key), 0xf1be5000u + uint64_t(ply));
    const float p_max = std::max(1 - d.density_eps, d.density_eps);
    const float fit = std::max(0.0f, 1 - d.fiber_radius);  // centres this far out keep the fiber inside
    std::vector<FiberRest> fibers;
    fibers.reserve(d.fibers());
    while (static_cast<int>(fibers.size()) < d.fibers()) {
        const float x = 2 * rng.next_float() - 1, y = 2 * rng.next_float() - 1;
        const float r = std::sqrt(x * x + y * y);
        const float keep = rng.next_float(), phase = 2 * kPi * rng.next_float();
        if (r > 1 || keep * p_max > fiber_density(r, d.density_eps, d.density_beta)) continue;
        fibers.push_back({r * fit, std::atan2(y, x), phase});
    }
    return fibers;
}

void append_fiber_curves(const CurveFrames& frames, const YarnDescription& d, const CurveSampling& plan,
                         uint32_t curve_key, int32_t id, YarnCurves& out) {
    const int plies = d.plies();
    const ArcLengthIndex index(frames);
    const YarnTwist twist = yarn_twist(frames, d);
    const double ply_length = double(index.length()) * twist.ply_stretch;

    // Migration cycles per metre of ply; whole cycles per loop on closed curves.
    double migration_rate = d.migration_frequency * std::fabs(twist.fiber_rate);
    if (plan.closed && ply_length > 0)
        migration_rate = std::round(migration_rate * ply_length / (2 * kPi)) * 2 * kPi / ply_length;

    // Ply frames at every sample, shared by that ply's fibers.
    const std::vector<float> arcs = sample_arc_lengths(plan, index.length());
    const size_t n = arcs.size();
    std::vector<PlyFrame> ply_frames(size_t(plies) * n);
    std::vector<double> ply_position(n);  // v: m of ply length at each sample
    for (size_t j = 0; j < n; ++j) {
        const CurvePoint yarn = index.point_at(arcs[j]);
        ply_position[j] = double(yarn.arc_length) * twist.ply_stretch;
        for (int i = 0; i < plies; ++i) {
            const PlyCentre c = ply_centre(yarn, d, twist, i);
            const Vec3 t = normalize(c.derivative);
            const Vec3 e1 = normalize(c.outward - t * dot(c.outward, t));
            ply_frames[size_t(i) * n + j] = {c.position, e1, cross(t, e1), c.radius};
        }
    }

    std::vector<Point4d> samples(n);
    const double rho_min = d.migration_rho_min, rho_span = d.migration_rho_max - d.migration_rho_min;
    for (int i = 0; i < plies; ++i) {
        for (const FiberRest& f : ply_fiber_rest_positions(d, curve_key, i)) {
            for (size_t j = 0; j < n; ++j) {
                const PlyFrame& p = ply_frames[size_t(i) * n + j];
                const double v = ply_position[j];
                const double angle = f.angle + twist.fiber_rate * v;
                const double r = f.radius * (rho_min + rho_span * 0.5 * (std::cos(migration_rate * v + f.migration_phase) + 1));
                const double cx = std::cos(angle) * r * p.radius, cy = std::sin(angle) * r * p.radius;
                Point4d& q = samples[j];
                q.v[0] = p.centre.x + cx * p.e1.x + cy * p.e2.x;
                q.v[1] = p.centre.y + cx * p.e1.y + cy * p.e2.y;
                q.v[2] = p.centre.z + cx * p.e1.z + cy * p.e2.z;
                q.v[3] = double(d.fiber_radius) * p.radius;
            }
            const std::vector<Vec4> points = fit_samples(plan, samples);
            out.add_curve(points.data(), points.size(), plan.closed, id);
        }
    }
}

}  // namespace purl
