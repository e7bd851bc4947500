#include "reference/ply_validation.h"

#include <algorithm>
#include <cmath>

#include "math/rng.h"
#include "reference/explicit_plies.h"
#include "yarn/curve_frames.h"
#include "yarn/straight_yarn.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

constexpr float kBack = 30.0f;  // ray origins start this many yarn radii before the yarn

// By atan2 of the sine and cosine: acos of a float cosine cannot tell angles below ~0.03 deg apart.
float degrees_between(Vec3 a, Vec3 b) {
    const Vec3 u = normalize(a), v = normalize(b);
    return std::atan2(length(cross(u, v)), dot(u, v)) * (180.0f / kPi);
}

bool finite_hit(const PlyHit& h) {
    return is_finite(h.point) && is_finite(h.normal) && is_finite(h.tangent) && is_finite(h.outward) &&
           std::isfinite(h.distance) && std::isfinite(h.exit_distance) && std::isfinite(h.u_ply) &&
           std::isfinite(h.v_ply) && std::isfinite(h.u_yarn) && std::isfinite(h.v_yarn) &&
           std::isfinite(h.arrangement_azimuth) && std::isfinite(h.t);
}

// The yarn, its frames and its explicit plies for one case.
struct Setup {
    std::vector<Vec4> points;
    CurveFrames frames;
    ExplicitPlies plies;
    explicit Setup(const ValidationCase& c)
        : points(validation_curve(c.curvature_radius)),
          frames(CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), c.curvature_radius > 0)),
          plies(frames, c.description) {}
};

struct Traced {
    bool tube = false;
    YarnTubeHit entry;
    float exit = 0;  // ray parameter where the ray leaves the tube
    ExplicitHit reference;
};

Traced trace_reference(const Setup& s, Vec3 origin, Vec3 direction) {
    Traced r;
    const ExplicitHit tube = s.plies.intersect_tube(origin, direction, 0, 3 * kBack);
    if (!tube.hit || !tube.resolved) return r;
    r.tube = true;
    r.entry = {origin, direction, tube.point, tube.segment, tube.t};
    r.exit = s.plies.tube_exit(origin, direction, tube.distance + 1e-4f, 3 * kBack, tube.segment, tube.t);
    r.reference = s.plies.intersect_plies(origin, direction, tube.distance - 1e-3f, r.exit + 1e-3f);
    return r;
}

// A ray at angle psi from the yarn's normal plane through the cross-section at (segment, t),
// passing `offset` yarn radii beside the centre-line, seen from azimuth `side`.
void make_ray(const CurveFrames& frames, uint32_t segment, float t, float psi, float side, float offset, float sense,
              Vec3& origin, Vec3& direction) {
    const CurvePoint c = frames.evaluate(segment, t);
    const Vec3 toward = c.normal * std::cos(side) + c.binormal * std::sin(side);
    direction = normalize(toward * -std::cos(psi) + c.tangent * (sense * std::sin(psi)));
    const Vec3 across = cross(c.tangent, toward);
    origin = c.position + across * (offset * c.radius) - direction * (kBack * c.radius);
}

}  // namespace

YarnDescription touching_plies(int plies, float ply_twist) {
    YarnDescription d = default_yarn_description();
    d.ply_count = static_cast<float>(plies);
    const float s = plies > 1 ? std::sin(kPi / plies) : 1.0f;
    d.ply_distance = plies > 1 ? 0.97f / (1 + s) : 0.0f;
    d.ply_radius = plies > 1 ? d.ply_distance * s : 0.97f;
    d.ply_twist = ply_twist;
    return d;
}

std::vector<Vec4> validation_curve(float curvature_radius) {
    std::vector<Vec4> points;
    if (curvature_radius <= 0) return straight_yarn_points();
    // Control points on a circle: the uniform B-spline runs at radius a (2 + cos step) / 3.
    const int n = std::max(24, static_cast<int>(std::ceil(2 * kPi * curvature_radius / 0.5f)));
    const float step = 2 * kPi / n;
    const float a = curvature_radius * 3 / (2 + std::cos(step));
    for (int i = 0; i < n + 3; ++i)
        points.emplace_back(a * std::cos(step * i), a * std::sin(step * i), 0.0f, 1.0f);
    return points;
}

double MethodStats::mean(const std::vector<float>& v) const {
    double sum = 0;
    for (float x : v) sum += x;
    return v.empty() ? 0.0 : sum / v.size();
}

double MethodStats::percentile(std::vector<float> v, double p) const {
    if (v.empty()) return 0.0;
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
}

PlyHit explicit_ply_answer(const CurveFrames& frames, const ExplicitPlies& plies, int ply_count,
                           const YarnTubeHit& hit, PlySearchStats* stats) {
    const float radius = frames.reference_radius();
    // Start a hair before the entry, so that a ply touching the tube there is not missed.
    const float back = 1e-3f * radius;
    const Vec3 origin = hit.point - hit.direction * back;
    const float exit = plies.tube_exit(origin, hit.direction, 2 * back, 8 * radius, hit.segment, hit.t);
    // A ply met farther along the yarn than the ray's passage can reach belongs to another
    // passage of the same yarn (a knit's loops touch and overlap theirs).
    const float here = project_to_centreline(frames, hit.point, hit.segment, hit.t).point.arc_length;
    const auto elsewhere = [&](const ExplicitHit& e) {
        float apart = std::fabs(frames.evaluate(e.segment, e.t).arc_length - here);
        if (frames.closed()) apart = std::min(apart, frames.total_length() - apart);
        return apart > exit + 2 * radius;
    };
    const ExplicitHit e = plies.intersect_plies(origin, hit.direction, 0, exit);
    PlyHit h;
    PlySearchStats spent;
    spent.converged = e.resolved;
    spent.evaluations = e.steps;
    if (stats) *stats = spent;
    h.exit_distance = exit - back;
    if (!e.hit) return h;
    h.hit = true;
    h.ply = e.ply;
    h.point = e.point, h.normal = e.normal, h.tangent = e.tangent;
    h.distance = e.distance - back;
    h.segment = e.segment, h.t = e.t;
    bool other_passage = elsewhere(e);
    for (int i = 0; i < ply_count; ++i) {
        const ExplicitHit crossing = plies.intersect_ply(i, origin, hit.direction, 0, exit);
        h.plies_crossed += crossing.hit;
        other_passage = other_passage || (crossing.hit && elsewhere(crossing));
    }
    if (stats) stats->converged = spent.converged && !other_passage;
    return h;
}

void compare_with_explicit(MethodStats& m, const PlyHit& h, const PlySearchStats& spent, const PlyHit& reference,
                           bool count_crossings) {
    ++m.rays;
    if (!finite_hit(h)) ++m.non_finite;
    if (!spent.converged) ++m.unconverged;
    m.iterations.push_back(spent.max_ply_evaluations);
    if (h.hit == reference.hit) ++m.agree;
    if (h.hit && !reference.hit) ++m.false_hits;
    if (!h.hit && reference.hit) ++m.false_misses;
    if (!h.hit || !reference.hit) return;
    ++m.both_hit;
    if (count_crossings) {
        ++m.crossed_checked;
        if (h.plies_crossed == reference.plies_crossed) ++m.crossed_agree;
    }
    if (h.ply != reference.ply) return;
    ++m.same_ply;
    m.normal_error.push_back(degrees_between(h.normal, reference.normal));
    m.tangent_error.push_back(degrees_between(h.tangent, reference.tangent));
    m.distance_error.push_back(std::fabs(h.distance - reference.distance));
}

ValidationResult validate_plies(const ValidationCase& c, const PlyTraceOptions& elliptical_options) {
    const Setup setup(c);
    const CurveFrames& frames = setup.frames;
    const YarnTwist twist = yarn_twist(frames, c.description);
    const uint32_t segments = frames.segment_count();
    const float psi = c.view_angle * kPi / 180.0f;
    PlyTraceOptions circular = elliptical_options;
    circular.cross_section = PlyCrossSection::circular;
    const PlyTraceOptions& elliptical = elliptical_options;

    ValidationResult result;
    Rng rng(c.seed, 0x5eed);
    int made = 0;
    for (int attempt = 0; made < c.rays && attempt < 4 * c.rays; ++attempt) {
        // Straight yarns: the middle fifth, away from the ends; loops: anywhere.
        const float g = c.curvature_radius > 0 ? rng.next_float() * segments
                                               : segments * (0.4f + 0.2f * rng.next_float());
        const uint32_t segment = std::min(static_cast<uint32_t>(g), segments - 1);
        const float side = 2 * kPi * rng.next_float();
        const float offset = 2 * rng.next_float() - 1;
        const float sense = rng.next_float() < 0.5f ? -1.0f : 1.0f;
        Vec3 origin, direction;
        make_ray(frames, segment, g - segment, psi, side, offset, sense, origin, direction);
        const Traced r = trace_reference(setup, origin, direction);
        if (!r.tube) continue;
        ++made;
        if (!r.reference.resolved) {
            ++result.reference_unresolved;
            continue;
        }
        PlyHit reference;
        reference.hit = r.reference.hit;
        reference.ply = r.reference.ply;
        reference.normal = r.reference.normal, reference.tangent = r.reference.tangent;
        reference.distance = r.reference.distance - length(r.entry.point - origin);
        // The explicit N_i needs one trace per ply: only every k-th ray pays for it.
        const bool count_crossings = c.count_crossings_every > 0 && made % c.count_crossings_every == 0;
        if (count_crossings) {
            const float entry = r.reference.hit ? r.reference.distance - 1e-3f : 0.0f;
            for (int p = 0; p < c.description.plies(); ++p)
                reference.plies_crossed += setup.plies.intersect_ply(p, origin, direction, entry, r.exit + 1e-3f).hit;
        }
        const auto compare = [&](MethodStats& m, const PlyTraceOptions& options) {
            PlySearchStats spent;
            const PlyHit h = trace_plies({frames, c.description, twist, r.entry}, options, &spent);
            compare_with_explicit(m, h, spent, reference, count_crossings);
        };
        compare(result.elliptical, elliptical);
        compare(result.circular, circular);
    }
    return result;
}

ValidationImage render_validation_image(const ValidationCase& c, int width, int height) {
    const Setup setup(c);
    const CurveFrames& frames = setup.frames;
    const YarnTwist twist = yarn_twist(frames, c.description);
    const float psi = c.view_angle * kPi / 180.0f;
    // Look at the middle of the yarn (straight) or at the loop's point on +x (loops).
    const uint32_t segment = c.curvature_radius > 0 ? 0 : frames.segment_count() / 2;
    const CurvePoint centre = frames.evaluate(segment, 0.0f);
    Vec3 toward, across, up;
    if (c.curvature_radius > 0) {
        toward = Vec3(0, 0, 1);  // from above the loop's plane
    } else {
        toward = Vec3(1, 0, 0);
    }
    Vec3 direction = normalize(toward * -std::cos(psi) + centre.tangent * std::sin(psi));
    across = normalize(cross(centre.tangent, toward));
    up = normalize(cross(direction, across));
    const float half_width = c.curvature_radius > 0 ? 1.6f : 1.25f;  // yarn radii
    const float half_height = half_width * height / width;

    ValidationImage img;
    img.width = width;
    img.height = height;
    const size_t n = size_t(width) * height;
    img.tube.assign(n, 0);
    img.explicit_hit.assign(n, 0);
    img.elliptical_hit.assign(n, 0);
    img.circular_hit.assign(n, 0);
    img.explicit_tangent.assign(n, Vec3(0.0f));
    img.elliptical_tangent.assign(n, Vec3(0.0f));
    img.circular_tangent.assign(n, Vec3(0.0f));
    img.explicit_normal.assign(n, Vec3(0.0f));
    img.elliptical_normal.assign(n, Vec3(0.0f));
    img.circular_normal.assign(n, Vec3(0.0f));
    PlyTraceOptions circular;
    circular.cross_section = PlyCrossSection::circular;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float u = ((x + 0.5f) / width * 2 - 1) * half_width;
            const float v = (1 - (y + 0.5f) / height * 2) * half_height;
            // Loops: the picture's horizontal axis crosses the yarn, vertical runs along it.
            const Vec3 origin = centre.position + across * u + up * v - direction * kBack;
            const Traced r = trace_reference(setup, origin, direction);
            const size_t i = size_t(y) * width + x;
            if (!r.tube) continue;
            img.tube[i] = 1;
            if (r.reference.hit && r.reference.resolved) {
                img.explicit_hit[i] = 1;
                img.explicit_tangent[i] = r.reference.tangent;
                img.explicit_normal[i] = r.reference.normal;
            }
            const PlyHit e = trace_plies({frames, c.description, twist, r.entry});
            if (e.hit) {
                img.elliptical_hit[i] = 1;
                img.elliptical_tangent[i] = e.tangent;
                img.elliptical_normal[i] = e.normal;
            }
            const PlyHit ci = trace_plies({frames, c.description, twist, r.entry}, circular);
            if (ci.hit) {
                img.circular_hit[i] = 1;
                img.circular_tangent[i] = ci.tangent;
                img.circular_normal[i] = ci.normal;
            }
        }
    }
    return img;
}

}  // namespace purl
