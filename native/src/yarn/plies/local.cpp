// The local method: every ply an analytic helix of the yarn straightened at the hit
// (local_helices.h). Per ply, nodes every quarter turn over the ray's stretch bracket the
// crossings, subdivided only where bounds on the helix leave room for a pair of crossings to
// hide between nodes; entries are computed in the order of a lower bound until none left can
// come first.
#include <algorithm>
#include <cmath>

#include "yarn/plies/bracketed_entry.h"
#include "yarn/plies/local_helices.h"
#include "yarn/plies/methods.h"
#include "yarn/plies/stretch.h"

namespace purl::plies {
namespace {

// One ply of the straightened yarn (a Helix for gap.h).
struct LocalHelix {
    struct Point {
        float s;
        Vec3 w, w1, w2;
    };
    const LocalHelices& m;
    int ply;
    float max_shift;

    Point at(float s) const {
        Point p{s, {}, {}, {}};
        m.at(ply, s, p.w, p.w1, &p.w2);
        return p;
    }
    Point moved(const Point& p, float ds) const { return at(p.s + ds); }
    HelixPoint view(const Point& p) const { return {p.w, p.w1, p.w2, m.ply_radius}; }
    Vec3 ray_at(float lambda) const { return m.ray * lambda; }
    float step_limit() const { return max_shift; }
};

// The crossing in [lo, hi] (f(lo) < 0 <= f(hi)): Newton steps kept inside the bracket. w and
// w1 there: once converged, the last evaluation's carried over the last step to first order.
float local_crossing(const LocalHelices& m, int ply, float lo, float hi, float f_lo, float f_hi, float tolerance,
                     Vec3& w, Vec3& w1) {
    float s = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    for (int step = 0; step < 8; ++step) {
        float slope;
        Vec3 w2;
        m.at(ply, s, w, w1, &w2);
        const float f = m.crossing(w, w1, &w2, &slope);
        if (f < 0) lo = s;
        else hi = s;
        float next = slope > 0 ? s - f / slope : 0.5f * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
        const float ds = next - s;
        s = next;
        if (std::fabs(ds) < tolerance) {
            w += w1 * ds;
            w1 += w2 * ds;
            return s;
        }
    }
    m.at(ply, s, w, w1, nullptr);
    return s;
}

// Where the ray (from the tube entry) enters ply `ply` near its crossing at s, whose closest
// approach lies at ray distance `approach`: the entry into the cylinder along the helix there,
// moved to the helix point closest to that entry. When that does not settle (a ray almost
// along the ply), the bracketed search. False when the ray misses the ply.
bool local_entry(const LocalHelices& m, int ply, float tolerance, float max_shift, float approach, float& s,
                 float& enter) {
    const float s_crossing = s;
    for (int step = 0; step < 6; ++step) {
        float leave;
        Vec3 w, w1, w2;
        m.at(ply, s, w, w1, &w2);
        if (!cross_ply_cylinder(Vec3(0.0f), m.ray, w, normalize(w1), m.ply_radius, enter, leave)) break;
        const Vec3 r = w - m.ray * std::max(enter, 0.0f);  // ply centre minus the entry point
        const float slope = dot(w1, w1) + dot(r, w2);
        const float ds = slope > 0 ? -dot(r, w1) / slope : 0.0f;
        if (std::fabs(ds) < tolerance) return true;
        s += clamp(ds, -max_shift, max_shift);
    }
    LocalHelix helix{m, ply, max_shift};
    LocalHelix::Point at;
    if (!bracketed_entry(helix, helix.at(s_crossing), approach, 0.0f, tolerance, at, enter)) return false;
    s = at.s;
    return true;
}

// The yarn's cross-section at s, from the local model (frame to first order, as the helices).
PlyCut local_cut(const PlyQuery& q, const CentrelineProjection& at, const LocalHelices& m, int ply, float s) {
    PlyCut cut;
    const CurvePoint& c = at.point;
    cut.g = at.segment + double(at.t) + s / std::max(c.speed, 1e-30f);
    cut.segment = at.segment;
    cut.t = at.t;
    q.frames.advance(cut.segment, cut.t, s / std::max(c.speed, 1e-30f));
    cut.yarn = c;
    const HelixAxes<Vec3>& a = m.world;
    cut.yarn.position = q.ray.point + a.c + a.tangent * s + a.kappa * (0.5f * s * s);
    cut.yarn.tangent = normalize(a.tangent + a.kappa * s);
    cut.yarn.normal = a.normal - a.tangent * (m.nk * s);
    cut.yarn.binormal = a.binormal - a.tangent * (m.bk * s);
    cut.yarn.arc_length = c.arc_length + s;
    const float total = q.frames.total_length();
    if (q.frames.closed() && total > 0) cut.yarn.arc_length -= total * std::floor(cut.yarn.arc_length / total);
    // The phase continues from the hit (a loop's seam must not jump it): ply_centre takes the
    // arc length, so give it the unwrapped phase directly.
    const float phase = m.phase + m.rate * s + 2 * kPi * ply / std::max(1, q.yarn.plies());
    cut.centre = ply_centre(cut.yarn, q.yarn, q.twist, phase, std::cos(phase), std::sin(phase));
    return cut;
}

// The least the squared miss distance D = |w|^2 can be over [a, b]: the cubic Hermite
// interpolant of D from the ends' values and slopes (D' = 2 f) less its error bound,
// max |D4| (b - a)^4 / 384, with the fourth derivative D4 = 2 (3 |w2|^2 + 4 w1.w3 + w.w4)
// bounded from `far` (|w| over the interval), `fastest` (|w1|) and the helix bounds.
float least_miss2(const LocalNode& a, const LocalNode& b, float far, float fastest, const HelixBounds& bounds) {
    const float h = b.s - a.s;
    const float d0 = sqr(a.miss), d1 = sqr(b.miss), s0 = 2 * a.f * h, s1 = 2 * b.f * h;
    // D(a + t h) = d0 + s0 t + c2 t^2 + c3 t^3 on t in [0, 1]; its least value at an end or
    // at a root of the slope s0 + 2 c2 t + 3 c3 t^2.
    const float c2 = 3 * (d1 - d0) - 2 * s0 - s1, c3 = 2 * (d0 - d1) + s0 + s1;
    float least = std::min(d0, d1);
    const auto consider = [&](float t) {
        if (t > 0 && t < 1) least = std::min(least, d0 + t * (s0 + t * (c2 + t * c3)));
    };
    // The slope's roots by the cancellation-free form (a root off by rounding would
    // overstate the least value).
    const float disc = c2 * c2 - 3 * c3 * s0;
    if (disc >= 0) {
        const float q = -(c2 + std::copysign(std::sqrt(disc), c2));
        if (c3 != 0) consider(q / (3 * c3));
        if (q != 0) consider(s0 / q);
    }
    const float snap = 2 * (3 * sqr(bounds.bend) + 4 * fastest * bounds.jerk + far * bounds.snap);
    return least - snap * sqr(sqr(h)) / 384;
}

// Calls visit(s, w, w1) (ply centre relative to the tube entry, its derivative) for every
// closest approach of ply `ply` to the ray in [s_lo, s_hi] that may be within its radius, and
// for a stretch end where the ply is within reach moving away (start) or toward the ray (end).
// The ply's distance to the ray changes by at most `bounds.speed` per m of s and its second
// derivative is at most `bounds.bend`, which bounds f' = |w1_perp|^2 + w_perp.w2_perp: an
// interval is skipped when the ply cannot come within reach at a root of f or anywhere in it
// (least_miss2), solved when f changes sign, and split only when f's slope bounds leave room
// for a pair of roots to hide between the nodes. Forced inline: out of line, the local query
// took 3 % more instructions.
template <class Visit>
[[gnu::always_inline]] inline void local_approaches(const LocalHelices& m, int ply, const LocalGrid& grid,
                                                   const HelixBounds& bounds, float tolerance, const Visit& visit) {
    const int steps = grid.steps;
    const float s_lo = grid.s[0], s_hi = grid.s[steps];
    const float speed_bound = bounds.speed, bend_bound = bounds.bend;
    const float reach2 = sqr(m.ply_radius + kGraze * tolerance);
    const float finest = 0.25f * m.ply_radius / speed_bound;
    const auto visit_end = [&](float s) {
        Vec3 w, w1;
        m.at(ply, s, w, w1, nullptr);
        visit(s, w, w1);
    };
    LocalNode prev = grid.node(0, ply);
    if (prev.f >= 0 && prev.miss <= m.ply_radius) visit_end(s_lo);
    for (int k = 1; k <= steps; ++k) {
        const LocalNode next = grid.node(k, ply);
        LocalNode stack[24][2];
        int depth = 0;
        stack[depth][0] = prev, stack[depth++][1] = next;
        while (depth > 0) {
            const LocalNode a = stack[--depth][0], b = stack[depth][1];
            const float width = b.s - a.s;
            if (0.5f * (a.miss + b.miss - speed_bound * width) > m.ply_radius) continue;
            // f, the slope of miss^2 / 2, has its own slope f' in [-fall, rise].
            const float slowest = std::max(std::min(a.pace, b.pace) - 0.5f * bend_bound * width, 0.0f);
            const float fastest = std::max(a.pace, b.pace) + 0.5f * bend_bound * width;
            const float far = std::max(a.miss, b.miss) + 0.5f * speed_bound * width;
            const float fall = far * bend_bound - slowest * slowest, rise = far * bend_bound + fastest * fastest;
            // At a root x of f, miss^2 >= miss(a)^2 - rise (x - a)^2 (likewise from b): the
            // least such bound over the interval, where both agree, must be within visit's reach.
            if (rise > 0) {
                const float from_a =
                    clamp(0.5f * width + 0.5f * (sqr(a.miss) - sqr(b.miss)) / (rise * width), 0.0f, width);
                if (std::max(sqr(a.miss) - rise * sqr(from_a), sqr(b.miss) - rise * sqr(width - from_a)) > reach2)
                    continue;
            }
            // Nowhere within reach (with a margin for the bound's own rounding).
            if (least_miss2(a, b, far, fastest, bounds) > 1.001f * reach2) continue;
            if (a.f < 0 && b.f >= 0) {
                Vec3 w, w1;
                const float s = local_crossing(m, ply, a.s, b.s, a.f, b.f, 10 * tolerance, w, w1);
                visit(s, w, w1);  // refined at the entry
                continue;
            }
            // A hidden rising root needs f to fall from a.f below zero or to b.f from above
            // it, and to rise from a.f or to b.f: skipped when the interval is too short for that.
            const float descent = std::max(a.f, 0.0f) + std::max(-b.f, 0.0f);
            const float ascent = std::max(-a.f, 0.0f) + std::max(b.f, 0.0f);
            if (fall < 0 || descent * rise + ascent * fall > width * fall * rise) continue;
            if (width < finest || depth + 2 > 24) continue;
            const LocalNode mid = local_node(m, ply, 0.5f * (a.s + b.s));
            stack[depth][0] = mid, stack[depth++][1] = b;  // the nearer half is examined first
            stack[depth][0] = a, stack[depth++][1] = mid;
        }
        prev = next;
    }
    if (prev.f < 0 && prev.miss <= m.ply_radius) visit_end(s_hi);
}

}  // namespace

// Out of line: inlined, it grew the scan past what GCC inlines into trace_local, +3 %
// instructions.
[[gnu::noinline]] LocalNode local_node(const LocalHelices& m, int ply, float s) {
    float cp, sp;
    m.phase_at(ply, s, cp, sp);
    return node_at(m, s, cp, sp);
}

PlyHit trace_local(const PlyQuery& q, const CentrelineProjection& at, const PlyTraceOptions& options, bool at_entry) {
    const YarnTubeHit& hit = q.ray;
    const auto pass = [&] {
        return at_entry ? pass_through(q.frames, hit, at) : pass_through(q.frames, hit, at.segment, at.t);
    };
    const CurvePoint& c = at.point;
    const float radius = std::max(c.radius, 1e-30f);
    const Vec3 across = cross(c.tangent, hit.direction);
    const float across_length = length(across);
    if (across_length < 1e-4f) return pass();

    LocalHelices m;
    m.world = {c.position - hit.point, c.tangent, c.curvature, c.normal, c.binormal};
    m.ray = hit.direction;
    m.nk = dot(c.normal, c.curvature);
    m.bk = dot(c.binormal, c.curvature);
    m.offset = q.yarn.ply_distance * radius;
    m.ply_radius = q.yarn.ply_radius * radius;
    m.rate = q.twist.ply_rate;
    m.phase = ply_phase(q.twist, c.arc_length);
    const int plies = std::min(std::max(1, q.yarn.plies()), kMaxPlies);
    m.set_offsets(plies);
    m.set_across(across / across_length);

    // The stretch the ray crosses, from the entry's own position along the yarn (it may lie
    // off the modelled cross-section); clipped to an open yarn's ends.
    const float along = dot(hit.direction, c.tangent), entry_s = dot(-m.world.c, c.tangent);
    const StraightStretch stretch =
        straight_stretch(c, radius, m.ply_radius, hit, std::fabs(along) / across_length, entry_s);
    float s_lo = stretch.lo, s_hi = stretch.hi;
    if (!q.frames.closed()) {
        s_lo = std::max(s_lo, -c.arc_length);
        s_hi = std::min(s_hi, q.frames.total_length() - c.arc_length);
    }
    if (!(s_hi > s_lo)) return pass();

    // Nodes every quarter turn of the plies (at most 64), subdivided where the ply may come
    // within reach of the ray: a sign change of f brackets a closest approach.
    const float quarter = 0.5f * kPi / std::max(std::fabs(m.rate), 1e-30f);
    const int steps = std::min(64, std::max(1, static_cast<int>(std::ceil((s_hi - s_lo) / quarter))));
    // Bounds over the stretch on |w1| and |w2| across the ray (the ply centre's speed and
    // acceleration seen along the ray): the yarn's own direction counts only as far as it
    // crosses the ray, which is little at grazing views.
    const float kappa = length(c.curvature), s_max = std::max(std::fabs(s_lo), std::fabs(s_hi));
    const float speed_bound = across_length * (1 + m.offset * kappa) + m.offset * std::fabs(m.rate) +
                              kappa * s_max * (1 + m.offset * std::fabs(m.rate));
    // Higher derivatives: the bend, the ply's turn (offset rate^k) and its lean on the bend
    // (the tangent times s lean(phase), lean's k-th derivative at most offset kappa rate^k).
    const float rate = std::fabs(m.rate), lean = m.offset * kappa;
    const HelixBounds bounds{speed_bound, kappa + m.offset * rate * rate + lean * rate * (2 + s_max * rate),
                             m.offset * rate * rate * rate + lean * rate * rate * (3 + s_max * rate),
                             m.offset * sqr(sqr(rate)) + lean * rate * rate * rate * (4 + s_max * rate)};
    const float tolerance = options.tolerance * radius;
    // Crossings within a ply radius (N_i counts their plies), then entries in the order of a
    // lower bound on each (the approach less twice the straight cylinder's half chord and a
    // ply radius: a margin for the helix's bend) until no remaining one can come first.
    struct Reach {
        int ply;
        float s, approach, earliest;
    };
    Reach reached[64];
    int count = 0;
    uint32_t crossed = 0;
    LocalGrid grid;
    grid.build(m, plies, s_lo, s_hi, steps);
    for (int ply = 0; ply < plies; ++ply) {
        const auto visit = [&](float sc, const Vec3& w, const Vec3& w1) {
            const float miss2 = m.miss2(w);
            if (miss2 > sqr(m.ply_radius + kGraze * tolerance) || count == 64) return;
            crossed |= 1u << ply;
            const float w1z = dot(w1, m.ray), pace = std::sqrt(std::max(dot(w1, w1) - w1z * w1z, 1e-12f));
            const float half_chord = std::sqrt(std::max(sqr(m.ply_radius) - miss2, 0.0f)) * length(w1) / pace;
            const float approach = dot(w, m.ray);
            int k = count++;
            for (; k > 0 && reached[k - 1].earliest > approach - 2 * half_chord - m.ply_radius; --k)
                reached[k] = reached[k - 1];
            reached[k] = {ply, sc, approach, approach - 2 * half_chord - m.ply_radius};
        };
        local_approaches(m, ply, grid, bounds, tolerance, visit);
    }
    int best_ply = -1;
    float best_enter = 1e30f, best_s = 0;
    for (int k = 0; k < count && reached[k].earliest < best_enter; ++k) {
        float se = reached[k].s, enter;
        if (local_entry(m, reached[k].ply, tolerance, s_hi - s_lo, reached[k].approach, se, enter) &&
            enter < best_enter) {
            best_enter = enter;
            best_ply = reached[k].ply;
            best_s = se;
        }
    }
    if (best_ply < 0) return pass();
    best_enter = std::max(best_enter, 0.0f);
    Candidate best{best_ply, local_cut(q, at, m, best_ply, best_s)};
    best.enter = best_enter;
    PlyHit out = finish_hit(best, hit.point + hit.direction * best_enter, q.twist, hit);
    out.plies_crossed = __builtin_popcount(crossed);
    return out;
}

}  // namespace purl::plies
