#include "yarn/implicit_plies.h"

#include <algorithm>
#include <cmath>

#include "yarn/yarn_tube.h"

namespace purl {
namespace {

float wrap_angle(float a) {
    a = std::fmod(a, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    return a >= 2 * kPi ? 0.0f : a;
}

// Ray (from the tube entry) against an infinite cylinder; false when it misses.
bool intersect_cylinder(Vec3 origin, Vec3 direction, Vec3 axis_point, Vec3 axis, float radius, float& enter,
                        float& leave) {
    const Vec3 w = origin - axis_point;
    const Vec3 w_perp = w - axis * dot(w, axis);
    const Vec3 d_perp = direction - axis * dot(direction, axis);
    const float a = dot(d_perp, d_perp), b = dot(w_perp, d_perp), c = dot(w_perp, w_perp) - radius * radius;
    if (a < 1e-12f) {  // running along the ply: inside or not at all
        if (c > 0) return false;
        enter = 0;
        leave = 1e30f;
        return true;
    }
    const float disc = b * b - a * c;
    if (disc < 0) return false;
    const float root = std::sqrt(disc);
    enter = (-b - root) / a;
    leave = (-b + root) / a;
    return leave > 0;
}

// Fixed-size scratch arrays left uninitialized: the per-query arrays below hold kilobytes of
// CurvePoints whose default member initializers would otherwise be zeroed on every query (a
// measurable share of a side-view query). Only trivially copyable aggregates are stored.
template <class T, int N>
struct Slots {
    union {
        T items[N];
    };
    Slots() {}
    T& operator[](int i) { return items[i]; }
    const T& operator[](int i) const { return items[i]; }
};

// One ply's centre-line at one cross-section of the yarn. The position along the curve is
// an unwrapped parameter g = segment + t: loops may run past their seam, open curves stop at
// their ends.
struct PlyCut {
    double g = 0;
    uint32_t segment = 0;
    float t = 0;
    CurvePoint yarn;
    PlyCentre centre;
};

void locate(const CachedCurve& frames, double g, uint32_t& segment, float& t) {
    const double n = frames.segment_count();
    if (frames.closed()) {
        g = std::fmod(g, n);
        if (g < 0) g += n;
    } else {
        g = std::min(std::max(g, 0.0), n);
    }
    segment = std::min(static_cast<uint32_t>(g), frames.segment_count() - 1);
    t = static_cast<float>(g - segment);
}

PlyCut cut_at(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply, double g) {
    PlyCut cut;
    cut.g = g;
    locate(frames, g, cut.segment, cut.t);
    cut.yarn = frames.evaluate(cut.segment, cut.t);
    cut.centre = ply_centre(cut.yarn, d, tw, ply);
    return cut;
}

// Closest approaches within a ply radius: one per crossed ply near side views, a few per ply
// at grazing angles.
constexpr int kMaxCandidates = 32;

struct Candidate {
    int ply = 0;
    PlyCut cut;
    float enter = 0, leave = 0;  // ray distances from the tube entry, m
    float approach = 0;          // ray distance of the closest approach to the ply centre-line, m
    bool fixed = false;          // from the circular fallback: `enter` is final
};

// The ply surface point, frame and coordinates for a hit at `point`.
PlyHit finish_hit(const Candidate& c, Vec3 point, const YarnTwist& tw, const YarnTubeHit& hit) {
    PlyHit h;
    h.hit = true;
    h.ply = c.ply;
    h.point = point;
    h.distance = std::max(c.enter, 0.0f);
    h.tangent = normalize(c.cut.centre.derivative);
    Vec3 radial = point - c.cut.centre.position;
    radial -= h.tangent * dot(radial, h.tangent);
    h.outward = c.cut.centre.outward - h.tangent * dot(c.cut.centre.outward, h.tangent);
    h.outward = normalize(h.outward);
    const float len = length(radial);
    // A hit on the ply's axis (only with a degenerate ray) faces the viewer.
    h.normal = len > 1e-12f ? radial / len : normalize(-hit.direction - h.tangent * dot(-hit.direction, h.tangent));
    if (!is_finite(h.normal)) h.normal = h.outward;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.v_ply = c.cut.yarn.arc_length * tw.ply_stretch;
    h.u_yarn = CurveFrames::azimuth(c.cut.yarn, point);
    h.v_yarn = c.cut.yarn.arc_length;
    h.arrangement_azimuth = wrap_angle(h.u_yarn - ply_phase(tw, c.cut.yarn.arc_length));
    h.segment = c.cut.segment;
    h.t = c.cut.t;
    return h;
}

PlyHit pass_through(const CurveFrames& frames, const YarnTubeHit& hit, uint32_t segment, float t) {
    PlyHit h;
    h.exit_distance = tube_chord_length(frames, segment, t, hit.point, hit.direction);
    h.point = hit.point + hit.direction * h.exit_distance;
    return h;
}

constexpr int kMaxScan = 32;  // sub-intervals of the yarn stretch scanned at most
constexpr int kMaxPlies = 16;  // plies with a precomputed phase offset (descriptions allow 12)

// cos and sin of every ply's fixed phase offset 2 pi i / N, for every N up to kMaxPlies: built
// once (thread-safe static), instead of 2N calls to cos and sin per query.
struct PlyOffsets {
    float cos[kMaxPlies + 1][kMaxPlies], sin[kMaxPlies + 1][kMaxPlies];
    PlyOffsets() {
        for (int n = 1; n <= kMaxPlies; ++n)
            for (int i = 0; i < n; ++i) {
                cos[n][i] = std::cos(2 * kPi * i / n);
                sin[n][i] = std::sin(2 * kPi * i / n);
            }
    }
};
const PlyOffsets& ply_offsets() {
    static const PlyOffsets table;
    return table;
}

// The plane through the ray in which a ply is cut, and the stretch of curve (in g) to search.
//  ply plane (default): holds the ray and the direction perpendicular to both the ray and the
//    ply's own tangent, so the ply's cut is an ellipse centred where its centre-line pierces
//    the plane: f(g) = (P - x0)_perp . P'_perp (perp: across the ray); rising roots are the
//    centre-line's closest approaches to the ray.
//  yarn plane (the paper's literal choice): holds the ray and the direction across the yarn at
//    the hit, one plane for all plies: f(g) = (P - x0) . n.
struct CuttingPlane {
    bool ply_plane = true;
    Vec3 x0, ray, normal;
    Vec3 side;  // ray x normal: with `normal`, coordinates across the ray
    float twist = 0;  // ply_rate, rad/m
    double g_lo = 0, g_hi = 0;
    double g_start = 0;  // the tube hit's cross-section
    int samples = 1;     // sub-intervals of [g_lo, g_hi] scanned for crossings
    // The yarn at the scan's sample points (evaluated once for all plies, when first needed)
    // and at g_start.
    bool sections_ready = false;
    Slots<CurvePoint, kMaxScan + 1> sections;
    uint32_t section_segment[kMaxScan + 1];
    float section_t[kMaxScan + 1];
    CurvePoint start;
    uint32_t start_segment = 0;
    float start_t = 0;
    // Ply phases by angle addition: each section's yarn phase (ply 0) turned by each ply's
    // fixed offset 2 pi i / N, so one sine and cosine per section serve all plies.
    float section_cos[kMaxScan + 1], section_sin[kMaxScan + 1];
    float start_cos = 1, start_sin = 0;
    const float* ply_cos = nullptr;  // cos and sin of 2 pi i / plies (from ply_offsets())
    const float* ply_sin = nullptr;
    int plies = 0;

    PlyCentre centre(const CurvePoint& yarn, const YarnDescription& d, const YarnTwist& tw, float base_cos,
                     float base_sin, int ply) const {
        if (ply >= plies) return ply_centre(yarn, d, tw, ply);
        const float phase = 2 * kPi * ply / plies + ply_phase(tw, yarn.arc_length);
        return ply_centre(yarn, d, tw, phase, base_cos * ply_cos[ply] - base_sin * ply_sin[ply],
                          base_sin * ply_cos[ply] + base_cos * ply_sin[ply]);
    }
};

struct PlaneOffset {
    float f, slope;  // f and df/dg
};
PlaneOffset plane_offset(const PlyCut& cut, const CuttingPlane& plane) {
    const PlyCentre& p = cut.centre;
    if (!plane.ply_plane)
        return {dot(p.position - plane.x0, plane.normal), dot(p.derivative, plane.normal) * cut.yarn.speed};
    auto across = [&](Vec3 v) { return v - plane.ray * dot(v, plane.ray); };
    const Vec3 w = across(p.position - plane.x0), d1 = across(p.derivative), d2 = across(p.second_derivative);
    return {dot(w, d1), (dot(d1, d1) + dot(w, d2)) * cut.yarn.speed};
}

// The crossings of one ply's centre-line through its plane, each by Newton steps kept
// inside its bracket (bisection when a step leaves it).
struct Pierces {
    Slots<PlyCut, 8> cuts;
    int count = 0;
    int evaluations = 0;
    bool converged = true;
};

bool bracketed_root(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply,
                    const CuttingPlane& plane, double lo, double hi, float f_lo, PlyCut cut, float tolerance,
                    int max_steps, Pierces& out) {
    const float rising = f_lo <= 0 ? 1.0f : -1.0f;  // f_lo's sign tells which side `lo` is on
    for (int step = 0; step <= max_steps; ++step) {
        const PlaneOffset o = plane_offset(cut, plane);
        double next = cut.g - o.f / o.slope;
        const bool newton = o.slope * rising > 0;
        if (newton && std::fabs(next - cut.g) * cut.yarn.speed < tolerance) {
            if (out.count < 8) out.cuts[out.count++] = cut;  // within tolerance of the root
            return true;
        }
        if (step == max_steps) break;
        if (o.f * rising < 0) lo = cut.g;
        else hi = cut.g;
        if (std::fabs(hi - lo) * cut.yarn.speed < tolerance) {
            if (out.count < 8) out.cuts[out.count++] = cut;
            return true;
        }
        if (!newton || !(next >= std::min(lo, hi) && next <= std::max(lo, hi))) next = 0.5 * (lo + hi);
        cut = cut_at(frames, d, tw, ply, next);
        ++out.evaluations;
    }
    return false;
}

struct Sample {
    PlyCut cut;
    PlaneOffset offset;
};

Sample sample_at(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply,
                 const CuttingPlane& plane, double g, Pierces& out) {
    Sample s{cut_at(frames, d, tw, ply, g), {}};
    s.offset = plane_offset(s.cut, plane);
    ++out.evaluations;
    return s;
}

void prepare_sections(const CachedCurve& frames, CuttingPlane& plane) {
    if (plane.sections_ready) return;
    for (int i = 0; i <= plane.samples; ++i) {
        locate(frames, plane.g_lo + (plane.g_hi - plane.g_lo) * i / plane.samples, plane.section_segment[i],
               plane.section_t[i]);
        plane.sections[i] = frames.evaluate(plane.section_segment[i], plane.section_t[i]);
        plane.section_cos[i] = std::cos(plane.twist * plane.sections[i].arc_length);
        plane.section_sin[i] = std::sin(plane.twist * plane.sections[i].arc_length);
    }
    plane.sections_ready = true;
}

// A sample at the scan's i-th point, from the section all plies share.
Sample shared_sample(const YarnDescription& d, const YarnTwist& tw, int ply, const CuttingPlane& plane, int i) {
    Sample s;
    s.cut.g = plane.g_lo + (plane.g_hi - plane.g_lo) * i / plane.samples;
    s.cut.segment = plane.section_segment[i];
    s.cut.t = plane.section_t[i];
    s.cut.yarn = plane.sections[i];
    s.cut.centre = plane.centre(s.cut.yarn, d, tw, plane.section_cos[i], plane.section_sin[i], ply);
    s.offset = plane_offset(s.cut, plane);
    return s;
}

// A root in (0, 1) of the cubic Hermite with values fa, fb (of opposite signs) and slopes p, q
// at 0 and 1: safeguarded Newton steps from the secant point, bisection when a step leaves the
// bracket. Pure arithmetic; only a start for the Newton steps on the real curve.
double hermite_root(double fa, double fb, double p, double q) {
    const double k3 = 2 * (fa - fb) + p + q, k2 = 3 * (fb - fa) - 2 * p - q;
    double lo = 0, hi = 1, u = fa / (fa - fb);
    const double rising = fa < 0 ? 1 : -1;
    for (int step = 0; step < 8; ++step) {
        const double f = ((k3 * u + k2) * u + p) * u + fa, slope = (3 * k3 * u + 2 * k2) * u + p;
        if (f * rising < 0) lo = u;
        else hi = u;
        double next = u - f / slope;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::fabs(next - u) < 1e-7) return next;
        u = next;
    }
    return u;
}

// Looks for crossings between two samples. Equal signs at both ends can still hide two
// crossings (the ray grazes a ply between two close approaches): where the cubic through the
// ends' values and slopes turns back toward zero, the interval is split and searched again.
void scan_interval(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply,
                   const CuttingPlane& plane, const Sample& a, const Sample& b, int depth,
                   const PlyTraceOptions& options, float tolerance, Pierces& out) {
    const float fa = a.offset.f, fb = b.offset.f;
    const bool crossing = plane.ply_plane ? (fa < 0 && fb >= 0) : ((fa <= 0) != (fb <= 0));
    if (crossing) {
        // First step from the root of the cubic through both ends' values and slopes (a much
        // better start than the secant over a piece of up to 1.5 rad of ply turn: it saves
        // about one curve evaluation per crossing).
        const double h = b.cut.g - a.cut.g;
        double g = a.cut.g + h * hermite_root(fa, fb, a.offset.slope * h, b.offset.slope * h);
        if (!std::isfinite(g)) g = 0.5 * (a.cut.g + b.cut.g);
        const PlyCut start = cut_at(frames, d, tw, ply, g);
        ++out.evaluations;
        if (!bracketed_root(frames, d, tw, ply, plane, a.cut.g, b.cut.g, fa, start, tolerance, options.max_iterations,
                            out))
            out.converged = false;
        return;
    }
    if ((fa < 0) != (fb < 0) || depth >= 3 || out.count >= 8) return;
    // Ends of one sign: where the cubic Hermite through both ends' values and slopes turns
    // back toward zero (within a quarter of the ends' size), there may be a pair of crossings.
    const double h = b.cut.g - a.cut.g;
    const double p = a.offset.slope * h, q = b.offset.slope * h;  // end slopes per unit of the interval
    const double k3 = 2 * (fa - fb) + p + q, k2 = 3 * (fb - fa) - 2 * p - q;  // f(u) = k3 u^3 + k2 u^2 + p u + fa
    const double c2 = 3 * k3, c1 = 2 * k2, c0 = p;
    double roots[2];
    int n_roots = 0;
    if (std::fabs(c2) > 1e-12) {
        const double disc = c1 * c1 - 4 * c2 * c0;
        if (disc >= 0) {
            roots[n_roots++] = (-c1 - std::sqrt(disc)) / (2 * c2);
            roots[n_roots++] = (-c1 + std::sqrt(disc)) / (2 * c2);
        }
    } else if (std::fabs(c1) > 1e-12) {
        roots[n_roots++] = -c0 / c1;
    }
    const double sign = fa < 0 ? -1.0 : 1.0, margin = 0.25 * std::min(std::fabs(fa), std::fabs(fb));
    double u = -1;
    for (int i = 0; i < n_roots; ++i) {
        const double r = roots[i];
        if (!(r > 0 && r < 1)) continue;
        const double value = ((k3 * r + k2) * r + p) * r + fa;
        if (value * sign < margin) u = r;  // turns back to (or past) zero
    }
    if (u < 0) return;
    u = clamp(static_cast<float>(u), 0.1f, 0.9f);
    const Sample m = sample_at(frames, d, tw, ply, plane, a.cut.g + h * u, out);
    scan_interval(frames, d, tw, ply, plane, a, m, depth + 1, options, tolerance, out);
    scan_interval(frames, d, tw, ply, plane, m, b, depth + 1, options, tolerance, out);
}

// Culling: can a ply's centre-line come within reach of the ray between two cuts whose
// positions and derivatives are known? The stretch is modelled by the cubic Hermite in arc
// length through both ends (exact at the ends; for a helix over 1.5 rad of turn it is off by
// about 1% of a yarn radius), and that cubic is bounded away from the ray: each quarter of it
// (a Bezier piece) lies in the hull of its control points, and all of them on the far side of a
// line at distance D across the ray means no point of the piece comes nearer than D. The
// model's own error is estimated from how far its second derivative at the ends is from the
// helix's (for the cubic Hermite the error is h^2/32 times that mismatch when the fourth
// derivative is steady) and allowed for three times over, plus 2% of a yarn radius.
bool beyond_reach(const PlyCut& a, const PlyCut& b, const CuttingPlane& plane, float yarn_radius) {
    const float h = b.yarn.arc_length - a.yarn.arc_length;
    if (!(h > 1e-6f * yarn_radius) || h > 8 * yarn_radius) return false;  // seam of a loop, or degenerate
    const Vec3 c0 = a.centre.position - plane.x0, c3 = b.centre.position - plane.x0;
    // The ends lie on the curve: one within the smallest reach settles it (the usual case for
    // a crossed ply) before the model's error is estimated.
    {
        const float near = std::max(a.centre.radius, b.centre.radius) + 0.02f * yarn_radius;
        const float e0 = sqr(dot(c0, plane.normal)) + sqr(dot(c0, plane.side));
        const float e3 = sqr(dot(c3, plane.normal)) + sqr(dot(c3, plane.side));
        if (e0 <= near * near || e3 <= near * near) return false;
    }
    const Vec3 c1 = c0 + a.centre.derivative * (h / 3), c2 = c3 - b.centre.derivative * (h / 3);
    const float inv_h2 = 6.0f / (h * h);
    const float mismatch = std::max(length(a.centre.second_derivative - (c0 - c1 * 2 + c2) * inv_h2),
                                    length(b.centre.second_derivative - (c1 - c2 * 2 + c3) * inv_h2));
    const float reach = std::max(a.centre.radius, b.centre.radius) + 3 * (h * h / 32) * mismatch +
                        0.02f * yarn_radius;
    // Across the ray: 2D coordinates in the plane perpendicular to it.
    const Vec3 e1 = plane.normal, e2 = plane.side;
    const Vec3 c[4] = {c0, c1, c2, c3};
    float x[4], y[4];
    for (int i = 0; i < 4; ++i) x[i] = dot(c[i], e1), y[i] = dot(c[i], e2);
    // The ends lie on the curve: one within reach settles it (the usual case for a crossed ply).
    const float reach2 = reach * reach;
    if (x[0] * x[0] + y[0] * y[0] <= reach2 || x[3] * x[3] + y[3] * y[3] <= reach2) return false;
    // The whole stretch's hull first, then its quarters.
    {
        const float mx = x[0] + x[1] + x[2] + x[3], my = y[0] + y[1] + y[2] + y[3];
        const float m = std::sqrt(mx * mx + my * my);
        float lower = 1e30f;
        for (int i = 0; i < 4; ++i) lower = std::min(lower, x[i] * mx + y[i] * my);
        if (lower > reach * m) return true;
    }
    // Bezier point and derivative at u (Bernstein form).
    auto point = [&](float u, float& px, float& py, float& dx, float& dy) {
        const float v = 1 - u;
        const float b0 = v * v * v, b1 = 3 * u * v * v, b2 = 3 * u * u * v, b3 = u * u * u;
        px = b0 * x[0] + b1 * x[1] + b2 * x[2] + b3 * x[3];
        py = b0 * y[0] + b1 * y[1] + b2 * y[2] + b3 * y[3];
        const float d0 = 3 * v * v, d1 = 6 * u * v, d2 = 3 * u * u;
        dx = d0 * (x[1] - x[0]) + d1 * (x[2] - x[1]) + d2 * (x[3] - x[2]);
        dy = d0 * (y[1] - y[0]) + d1 * (y[2] - y[1]) + d2 * (y[3] - y[2]);
    };
    float px0, py0, dx0, dy0;
    point(0, px0, py0, dx0, dy0);
    for (int k = 1; k <= 4; ++k) {
        float px1, py1, dx1, dy1;
        point(0.25f * k, px1, py1, dx1, dy1);
        // The quarter's control points (its length in u is 1/4, so derivatives scale by 1/12).
        const float qx[4] = {px0, px0 + dx0 / 12, px1 - dx1 / 12, px1};
        const float qy[4] = {py0, py0 + dy0 / 12, py1 - dy1 / 12, py1};
        const float mx = qx[0] + qx[1] + qx[2] + qx[3], my = qy[0] + qy[1] + qy[2] + qy[3];
        const float m = std::sqrt(mx * mx + my * my);
        float lower = 1e30f;
        for (int i = 0; i < 4; ++i) lower = std::min(lower, qx[i] * mx + qy[i] * my);
        if (!(lower > reach * m)) return false;
        px0 = px1, py0 = py1, dx0 = dx1, dy0 = dy1;
    }
    return true;
}

// Below this many plies a side-view ray crosses most of them anyway: culling would cost more
// (two shared evaluations and the bounds) than it saves.
constexpr int kSideCullPlies = 5;

Pierces pierce(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply,
               CuttingPlane& plane, const PlyTraceOptions& options, float radius) {
    Pierces out;
    const float tolerance = options.tolerance * radius;
    if (plane.ply_plane && plane.samples == 1 && options.cull && d.plies() >= kSideCullPlies) {
        // Near side views: cull a ply that stays out of reach of the ray on both sides of the
        // tube hit's cross-section (the window's ends are evaluated once for all plies).
        if (!plane.sections_ready) {
            out.evaluations += plane.samples + 1;
            prepare_sections(frames, plane);
        }
        PlyCut start;
        start.g = plane.g_start;
        start.yarn = plane.start;
        start.centre = plane.centre(start.yarn, d, tw, plane.start_cos, plane.start_sin, ply);
        const Sample lo = shared_sample(d, tw, ply, plane, 0), hi = shared_sample(d, tw, ply, plane, 1);
        if (beyond_reach(lo.cut, start, plane, radius) && beyond_reach(start, hi.cut, plane, radius)) return out;
    }
    if (plane.samples == 1) {
        // Near side views: Newton from the tube hit's cross-section (the paper's start), kept
        // in the window. A few steps settle on the crossing, or hand over to the scan below.
        PlyCut cut;
        cut.g = plane.g_start;
        cut.segment = plane.start_segment;
        cut.t = plane.start_t;
        cut.yarn = plane.start;
        cut.centre = plane.centre(cut.yarn, d, tw, plane.start_cos, plane.start_sin, ply);
        for (int step = 0; step < 4 && step < options.max_iterations; ++step) {
            const PlaneOffset o = plane_offset(cut, plane);
            if (!(o.slope > 0)) break;
            const double next = cut.g - o.f / o.slope;
            if (next < plane.g_lo || next > plane.g_hi) break;
            if (std::fabs(next - cut.g) * cut.yarn.speed < tolerance) {
                out.cuts[out.count++] = cut;
                return out;
            }
            cut = cut_at(frames, d, tw, ply, next);
            ++out.evaluations;
        }
    }
    if (!plane.sections_ready) {
        out.evaluations += plane.samples + 1;
        prepare_sections(frames, plane);
    }
    Sample previous = shared_sample(d, tw, ply, plane, 0);
    for (int i = 1; i <= plane.samples && out.count < 8; ++i) {
        const Sample next = shared_sample(d, tw, ply, plane, i);
        if (!(plane.ply_plane && options.cull && beyond_reach(previous.cut, next.cut, plane, radius)))
            scan_interval(frames, d, tw, ply, plane, previous, next, 0, options, tolerance, out);
        previous = next;
    }
    return out;
}

// The circular method for one ply: the ray projected into the perpendicular cross-section at
// the tube hit, against the ply's circle there. `enter` is the matching distance along the 3D
// ray; false when the projected ray misses the circle.
bool circular_cut_hit(const YarnTubeHit& hit, const CentrelineProjection& at, const PlyCentre& centre, float& enter,
                      Vec3& normal) {
    const Vec3 tangent = at.point.tangent;
    Vec3 flat = hit.direction - tangent * dot(hit.direction, tangent);
    const float flat_length = length(flat);
    if (flat_length < 1e-4f) return false;
    flat = flat / flat_length;
    const Vec3 x0 = hit.point - tangent * dot(hit.point - at.point.position, tangent);
    const Vec3 w = x0 - centre.position;
    const float b = dot(w, flat), c = dot(w, w) - sqr(centre.radius);
    const float disc = b * b - c;
    if (disc < 0) return false;
    const float root = std::sqrt(disc);
    if (-b + root <= 0) return false;
    const float along = std::max(-b - root, 0.0f);
    enter = along / flat_length;
    normal = normalize(w + flat * along);
    return true;
}

PlyCut cut_at_hit(const CentrelineProjection& at, const YarnDescription& d, const YarnTwist& tw, int ply) {
    PlyCut cut;
    cut.g = at.segment + double(at.t);
    cut.segment = at.segment;
    cut.t = at.t;
    cut.yarn = at.point;
    cut.centre = ply_centre(at.point, d, tw, ply);
    return cut;
}

PlyHit trace_circular(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw,
                      const YarnTubeHit& hit, const CentrelineProjection& at) {
    Candidate best;
    bool found = false;
    int crossed = 0;
    Vec3 best_normal;
    for (int ply = 0; ply < d.plies(); ++ply) {
        const PlyCut cut = cut_at_hit(at, d, tw, ply);
        float enter;
        Vec3 normal;
        if (!circular_cut_hit(hit, at, cut.centre, enter, normal)) continue;
        ++crossed;
        if (found && enter >= best.enter) continue;
        found = true;
        best.ply = ply;
        best.cut = cut;
        best.enter = enter;
        best_normal = normal;
    }
    if (!found) return pass_through(frames, hit, at.segment, at.t);
    PlyHit h = finish_hit(best, hit.point + hit.direction * best.enter, tw, hit);
    // The circular method's normal is the 2D one, in the frozen cross-section.
    h.normal = best_normal;
    const Vec3 side = cross(h.tangent, h.outward);
    h.u_ply = wrap_angle(std::atan2(dot(h.normal, side), dot(h.normal, h.outward)));
    h.plies_crossed = crossed;
    return h;
}

// Newton step (in metres of yarn) toward the point of the ply centre-line closest to x:
// the root of (P - x).P', with derivative |P'|^2 + (P - x).P''.
float closest_point_step(const PlyCut& cut, Vec3 x) {
    const Vec3 w = cut.centre.position - x, d1 = cut.centre.derivative;
    const float slope = dot(d1, d1) + dot(w, cut.centre.second_derivative);
    return -dot(w, d1) / std::max(slope, 0.25f * dot(d1, d1));
}

// Distance from the ray point at `lambda` to the ply surface (negative inside), with `cut`
// moved to the helix point closest to it.
float helix_gap(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                int ply, float lambda, PlyCut& cut, int& evaluations) {
    const Vec3 x = hit.point + hit.direction * lambda;
    for (int step = 0; step < 3; ++step) {
        const float ds = closest_point_step(cut, x);
        cut = cut_at(frames, d, tw, ply, cut.g + ds / std::max(cut.yarn.speed, 1e-30f));
        ++evaluations;
        if (std::fabs(ds) < 1e-4f * cut.centre.radius) break;
    }
    const Vec3 r = x - cut.centre.position;
    const Vec3 axis = normalize(cut.centre.derivative);
    return length(r - axis * dot(r, axis)) - cut.centre.radius;
}

// Where the ray enters the ply around one closest approach: the entry into the cut's
// cylinder, moved a few times to the cylinder at the helix point closest to it. If that does
// not settle (the ray runs nearly along the ply), a bracketed search on the distance to the
// helix between the tube entry and the closest approach. False when the ray misses the ply.
bool enter_ply(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
               bool exact_approach, float tolerance, int refinements, float max_shift, Candidate& cand,
               int& evaluations) {
    PlyCut cut = cand.cut;
    const float lambda_max = exact_approach ? std::max(cand.approach, 0.0f) : 1e30f;
    bool hits = intersect_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                   cut.centre.radius, cand.enter, cand.leave);
    if (!hits && !exact_approach) return false;
    float lambda = hits ? clamp(cand.enter, 0.0f, lambda_max) : lambda_max;
    for (int r = 0; r < refinements; ++r) {
        const Vec3 x = hit.point + hit.direction * lambda;
        const float ds = clamp(closest_point_step(cut, x), -max_shift, max_shift);
        if (hits && std::fabs(ds) < tolerance) {  // settled: this cut's cylinder is the answer
            cand.cut = cut;
            cand.enter = lambda;
            return true;
        }
        cut = cut_at(frames, d, tw, cand.ply, cut.g + ds / std::max(cut.yarn.speed, 1e-30f));
        ++evaluations;
        hits = intersect_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                  cut.centre.radius, cand.enter, cand.leave);
        if (!hits) break;
        lambda = clamp(cand.enter, 0.0f, lambda_max);
        if (std::fabs(ds) < tolerance) {
            cand.cut = cut;
            cand.enter = lambda;
            return true;
        }
    }
    if (!exact_approach) {  // the yarn-plane variant has no bracket: keep the last cylinder
        cand.cut = cut;
        cand.enter = lambda;
        return hits;
    }
    // Bracket: outside at the tube entry (else the ray starts in the ply), inside at the approach.
    cut = cand.cut;
    float lo = 0, hi = lambda_max;
    PlyCut lo_cut = cut, hi_cut = cut;
    float h_lo = helix_gap(frames, d, tw, hit, cand.ply, lo, lo_cut, evaluations);
    if (h_lo <= 0) {
        cand.cut = lo_cut;
        cand.enter = 0;
        return true;
    }
    float h_hi = helix_gap(frames, d, tw, hit, cand.ply, hi, hi_cut, evaluations);
    if (h_hi > 0) return false;
    for (int step = 0; step < 30 && hi - lo > tolerance; ++step) {
        float mid = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);
        if (!(mid > lo + 0.05f * (hi - lo) && mid < hi - 0.05f * (hi - lo))) mid = 0.5f * (lo + hi);
        PlyCut mid_cut = h_hi > -h_lo ? lo_cut : hi_cut;
        const float h = helix_gap(frames, d, tw, hit, cand.ply, mid, mid_cut, evaluations);
        if (h > 0) lo = mid, h_lo = h, lo_cut = mid_cut;
        else hi = mid, h_hi = h, hi_cut = mid_cut;
    }
    cand.cut = hi_cut;
    cand.enter = hi;
    return true;
}

PlyHit trace_elliptical(const CurveFrames& yarn_frames, const YarnDescription& d, const YarnTwist& tw,
                        const YarnTubeHit& hit, const CentrelineProjection& at, const PlyTraceOptions& options) {
    // The few segments the ray's stretch spans are expanded once and reused by every ply's
    // scan and Newton steps.
    const CachedCurve frames(yarn_frames);
    const CurvePoint& c = at.point;
    const Vec3 across = cross(c.tangent, hit.direction);
    const float across_length = length(across);
    if (across_length < 1e-4f) return pass_through(yarn_frames, hit, at.segment, at.t);
    const float radius = c.radius;

    CuttingPlane plane;
    plane.ply_plane = options.cross_section == PlyCrossSection::elliptical;
    plane.x0 = hit.point;
    plane.ray = hit.direction;
    plane.normal = normalize(cross(hit.direction, across / across_length));
    plane.side = cross(plane.ray, plane.normal);

    // The stretch of yarn the ray crosses: entry to exit of the straight tube at the hit,
    // widened by how far along the yarn a ply's cut can reach.
    const Vec3 w = hit.point - c.position;
    const Vec3 w_perp = w - c.tangent * dot(w, c.tangent);
    const Vec3 d_perp = hit.direction - c.tangent * dot(hit.direction, c.tangent);
    const float a = dot(d_perp, d_perp), b = dot(w_perp, d_perp);
    const float chord = (-b + std::sqrt(std::max(b * b - a * std::min(dot(w_perp, w_perp) - radius * radius, 0.0f), 0.0f))) / a;
    const float along = dot(hit.direction, c.tangent);
    const float tan_psi = std::fabs(along) / across_length;
    const float ply_radius = d.ply_radius * radius;
    const float margin = ply_radius * (1 + tan_psi) + 0.05f * radius + 0.1f * chord * std::fabs(along);
    float s_lo = std::min(0.0f, chord * along) - margin, s_hi = std::max(0.0f, chord * along) + margin;
    const double g0 = at.segment + double(at.t), inv_speed = 1.0 / std::max(c.speed, 1e-30f);
    plane.g_start = g0;
    plane.g_lo = g0 + s_lo * inv_speed;
    plane.g_hi = g0 + s_hi * inv_speed;
    if (length(c.curvature) * radius > 0.02f) {
        // On a bend the straight tube's chord is only a guess: find where the ray really leaves.
        const TubeExit exit = tube_exit(yarn_frames, at.segment, at.t, hit.point, hit.direction);
        double g_exit = exit.segment + double(exit.t), n = frames.segment_count();
        if (frames.closed()) g_exit = g0 + std::remainder(g_exit - g0, n);
        const double pad = margin * inv_speed;
        plane.g_lo = std::min(plane.g_lo, std::min(g0, g_exit) - pad);
        plane.g_hi = std::max(plane.g_hi, std::max(g0, g_exit) + pad);
        s_lo = static_cast<float>((plane.g_lo - g0) * c.speed);
        s_hi = static_cast<float>((plane.g_hi - g0) * c.speed);
    }
    if (!frames.closed()) {  // open yarns end: no plies beyond them
        plane.g_lo = std::max(plane.g_lo, 0.0);
        plane.g_hi = std::min(plane.g_hi, double(frames.segment_count()));
        s_lo = static_cast<float>((plane.g_lo - g0) * c.speed);
        s_hi = static_cast<float>((plane.g_hi - g0) * c.speed);
    }
    // A ply's closest approaches to the ray are about a turn apart: sub-intervals of at most
    // scan_turn radians of ply turn hold at most one each.
    const float per_interval = std::min(options.scan_turn / std::max(std::fabs(tw.ply_rate), 1e-30f),
                                        options.scan_length * radius);
    plane.samples = std::min(kMaxScan, 1 + static_cast<int>((s_hi - s_lo) / per_interval));
    // The Newton start is the tube hit's own cross-section, already evaluated, unless a
    // clipped window moved it.
    int evaluations = 0;
    if (plane.g_start >= plane.g_lo && plane.g_start <= plane.g_hi) {
        plane.start = c;
        plane.start_segment = at.segment;
        plane.start_t = at.t;
    } else {
        plane.g_start = std::min(std::max(plane.g_start, plane.g_lo), plane.g_hi);
        locate(frames, plane.g_start, plane.start_segment, plane.start_t);
        plane.start = frames.evaluate(plane.start_segment, plane.start_t);
        ++evaluations;
    }
    plane.twist = tw.ply_rate;
    plane.start_cos = std::cos(tw.ply_rate * plane.start.arc_length);
    plane.start_sin = std::sin(tw.ply_rate * plane.start.arc_length);
    plane.plies = std::min(std::max(1, d.plies()), kMaxPlies);
    plane.ply_cos = ply_offsets().cos[plane.plies];
    plane.ply_sin = ply_offsets().sin[plane.plies];
    const float half = s_hi - s_lo;  // bound on refinement steps, m

    // A closest approach within the ply radius is a crossing; where the ray enters the ply
    // there comes from the cut's cylinder, corrected against the helix (enter_ply).
    const float tolerance = options.tolerance * radius;
    uint32_t crossed_mask = 0;
    bool converged = true;
    int best = -1, worst = 0;
    Slots<Candidate, kMaxCandidates> candidates;
    int count = 0;
    for (int ply = 0; ply < d.plies(); ++ply) {
        Pierces p = pierce(frames, d, tw, ply, plane, options, radius);
        evaluations += p.evaluations;
        worst = std::max(worst, p.evaluations);
        if (!p.converged) {
            // Fallback: this ply as the circular method sees it, at the tube hit's cross-section.
            converged = false;
            Candidate cand{ply, cut_at_hit(at, d, tw, ply)};
            Vec3 normal;
            cand.fixed = circular_cut_hit(hit, at, cand.cut.centre, cand.enter, normal);
            if (cand.fixed && count < kMaxCandidates) candidates[count++] = cand;
        }
        for (int k = 0; k < p.count; ++k) {
            Candidate cand{ply, p.cuts[k]};
            const Vec3 w = cand.cut.centre.position - hit.point;
            cand.approach = dot(w, hit.direction);
            const float miss = length(w - hit.direction * cand.approach);
            if (miss > cand.cut.centre.radius && plane.ply_plane) continue;  // passes beside the ply
            if (count < kMaxCandidates) candidates[count++] = cand;
        }
    }
    for (int i = 0; i < count; ++i) {
        Candidate& cand = candidates[i];
        if (!cand.fixed &&
            !enter_ply(frames, d, tw, hit, plane.ply_plane, tolerance, options.refinements, half, cand, evaluations))
            continue;
        crossed_mask |= 1u << cand.ply;
        if (best < 0 || cand.enter < candidates[best].enter) best = i;
    }
    if (best >= 0) {
        const Candidate& cand = candidates[best];
        const Vec3 point = hit.point + hit.direction * std::max(cand.enter, 0.0f);
        PlyHit h = finish_hit(cand, point, tw, hit);
        h.plies_crossed = __builtin_popcount(crossed_mask);
        h.iterations = evaluations;
        h.max_ply_iterations = worst;
        h.converged = converged;
        return h;
    }
    PlyHit h = pass_through(yarn_frames, hit, at.segment, at.t);
    h.iterations = evaluations;
    h.max_ply_iterations = worst;
    h.converged = converged;
    return h;
}

}  // namespace

PlyHit trace_plies(const CurveFrames& frames, const YarnDescription& d, const YarnTubeHit& hit,
                   const PlyTraceOptions& options) {
    return trace_plies(frames, d, yarn_twist(frames, d), hit, options);
}

PlyHit trace_plies(const CurveFrames& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                   const PlyTraceOptions& options) {
    const CentrelineProjection at = project_to_centreline(frames, hit.point, hit.segment, hit.t);
    return options.cross_section == PlyCrossSection::circular ? trace_circular(frames, d, tw, hit, at)
                                                              : trace_elliptical(frames, d, tw, hit, at, options);
}

}  // namespace purl
