// The exact (elliptical) method: crossings and entries found on the model of the yarn
// (exact_search.h), then settled on the exact curve: crossings the model cannot decide, and
// entries in the order of the model's until none left can come first.
#include <algorithm>
#include <cmath>
#include <limits>

#include "yarn/plies/bracketed_entry.h"
#include "yarn/plies/exact_search.h"
#include "yarn/plies/methods.h"

namespace purl::plies {
namespace {

// One ply of the query on the exact curve (a Helix for gap.h); every evaluation is counted.
struct ExactHelix {
    using Point = PlyCut;
    const CachedCurve& frames;
    const PlyQuery& q;
    int ply;
    int evaluations = 0;

    PlyCut at(double g) {
        ++evaluations;
        return cut_at(frames, q.yarn, q.twist, ply, g);
    }
    PlyCut moved(const PlyCut& c, float ds) { return at(c.g + ds / std::max(c.yarn.speed, 1e-30f)); }
    static HelixPoint view(const PlyCut& c) {
        return {c.centre.position, c.centre.derivative, c.centre.second_derivative, c.centre.radius};
    }
    Vec3 ray_at(float lambda) const { return q.ray.point + q.ray.direction * lambda; }
    // The walk to the closest point is not limited: a step is at most four distances long.
    static float step_limit() { return std::numeric_limits<float>::infinity(); }
};

// How the entry searches step: Newton's tolerance (m), walk steps, the longest step (m).
struct EntrySteps {
    float tolerance;
    int refinements;
    float max_shift;
};

// Where the ray enters the ply around one closest approach: the entry into the cut's
// cylinder, moved a few times to the cylinder at the helix point closest to it. If that does
// not settle (the ray runs nearly along the ply), the bracketed search between the tube entry
// and the closest approach. False when the ray misses the ply.
bool enter_ply(ExactHelix& helix, const EntrySteps& steps, Candidate& cand) {
    const YarnTubeHit& hit = helix.q.ray;
    PlyCut cut = cand.cut;
    const float lambda_max = std::max(cand.approach, 0.0f);
    float leave;
    bool hits = cross_ply_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                   cut.centre.radius, cand.enter, leave);
    float lambda = hits ? clamp(cand.enter, 0.0f, lambda_max) : lambda_max;
    const auto settle = [&] {  // this cut's cylinder is the answer
        cand.cut = cut;
        cand.enter = lambda;
        return true;
    };
    for (int r = 0; r < steps.refinements; ++r) {
        const HelixPoint p = ExactHelix::view(cut);
        const float ds =
            clamp(closest_point_step(p.position, p.d1, p.d2, helix.ray_at(lambda)), -steps.max_shift, steps.max_shift);
        if (hits && std::fabs(ds) < steps.tolerance) return settle();
        cut = helix.moved(cut, ds);
        hits = cross_ply_cylinder(hit.point, hit.direction, cut.centre.position, normalize(cut.centre.derivative),
                                  cut.centre.radius, cand.enter, leave);
        if (!hits) break;
        lambda = clamp(cand.enter, 0.0f, lambda_max);
        if (std::fabs(ds) < steps.tolerance) return settle();
    }
    return bracketed_entry(helix, cand.cut, cand.approach, kGraze * steps.tolerance, steps.tolerance, cand.cut,
                           cand.enter);
}

// A model crossing's curve parameter and its bracket's ends.
struct CurveBracket {
    double g, lo, hi;
};

// Exact Newton steps on f = (P - x0)_perp . P'_perp (the crossing across the ray) from the
// model's crossing, inside the model's bracket: settles a crossing whose miss distance is too
// close to the ply radius for the model to decide. False when a step leaves the bracket or the
// steps run out.
bool exact_crossing(ExactHelix& helix, const CurveBracket& bracket, float tolerance, int max_steps, PlyCut& cut) {
    const YarnTubeHit& hit = helix.q.ray;
    auto across = [&](Vec3 v) { return v - hit.direction * dot(v, hit.direction); };
    cut = helix.at(bracket.g);
    for (int step = 0; step < max_steps; ++step) {
        const PlyCentre& p = cut.centre;
        const Vec3 w = across(p.position - hit.point), d1 = across(p.derivative), d2 = across(p.second_derivative);
        const float f = dot(w, d1), slope = dot(d1, d1) + dot(w, d2);
        if (!(slope > 0)) return false;
        const float ds = -f / slope;  // m of yarn
        if (std::fabs(ds) < tolerance) return true;
        const double next = cut.g + ds / std::max(cut.yarn.speed, 1e-30f);
        if (!(next >= std::min(bracket.lo, bracket.hi) && next <= std::max(bracket.lo, bracket.hi))) return false;
        cut = helix.at(next);
    }
    return false;
}

}  // namespace

PlyHit trace_exact(const CachedCurve& frames, const PlyQuery& q, const CentrelineProjection& at,
                   const PlyTraceOptions& options, PlySearchStats& stats) {
    const YarnTubeHit& hit = q.ray;
    const CurvePoint& c = at.point;
    const Vec3 across = cross(c.tangent, hit.direction);
    const float across_length = length(across);
    if (across_length < 1e-4f) return pass_through(frames, hit, at);
    const float radius = c.radius;
    const float along = dot(hit.direction, c.tangent);
    const Stretch stretch = ray_stretch(frames, q.yarn, hit, at, std::fabs(along) / across_length);
    if (!(stretch.s_hi - stretch.s_lo > 1e-6f * radius))
        return stretch.exit_distance >= 0 ? pass_through(hit, stretch.exit_distance) : pass_through(frames, hit, at);

    ModelSearch search(frames, q.yarn, q.twist, hit, stretch, radius, options,
                       normalize(cross(hit.direction, across / across_length)), along >= 0);
    ModelCrossings found;
    search.run(found);
    const YarnModel& m = search.model();
    const float tolerance = search.tolerance();
    int evaluations = found.evaluations;

    // Ambiguous misses settled on the curve, then entries refined in the order of the model's,
    // until the next model entry (less its slack) is past the best exact one.
    uint32_t crossed_mask = found.sure;
    int order[kMaxWork];
    int kept = 0;
    for (int i = 0; i < found.count; ++i) {
        ModelCandidate& mc = found.items[i];
        if (mc.ambiguous) {
            ExactHelix helix{frames, q, mc.ply};
            PlyCut cut;
            mc.ambiguous = exact_crossing(helix, {m.g(mc.piece, mc.s_cross), m.g(mc.piece, mc.s_lo),
                                                  m.g(mc.piece, mc.s_hi)},
                                          tolerance, std::max(options.max_iterations, 1), cut);
            evaluations += helix.evaluations;
            if (mc.ambiguous) {  // settled: the exact miss decides, and a graze needs the exact approach
                const Vec3 w = cut.centre.position - hit.point;
                mc.approach = dot(w, hit.direction);
                if (length(w - hit.direction * mc.approach) > cut.centre.radius + kGraze * tolerance) continue;
            } else if (mc.miss > 0) {
                continue;  // not settled: the model's own miss decides
            }
        }
        crossed_mask |= 1u << mc.ply;
        int k = kept++;  // insertion by entry less slack
        for (; k > 0 && found.items[order[k - 1]].enter - found.items[order[k - 1]].slack > mc.enter - mc.slack; --k)
            order[k] = order[k - 1];
        order[k] = i;
    }
    Candidate best;
    bool hit_found = false;
    const EntrySteps steps{tolerance, options.refinements, search.shift()};
    for (int n = 0; n < kept; ++n) {
        const ModelCandidate& mc = found.items[order[n]];
        if (hit_found && mc.enter - mc.slack >= best.enter) break;
        // From the model's helix point nearest the entry: usually within tolerance already.
        ExactHelix helix{frames, q, mc.ply};
        Candidate cand{mc.ply, helix.at(m.g(mc.piece_enter, mc.s_enter))};
        cand.approach = mc.approach;
        if (enter_ply(helix, steps, cand)) {
            if (!hit_found || cand.enter < best.enter) best = cand;
            hit_found = true;
        }
        evaluations += helix.evaluations;
        stats.max_ply_evaluations = std::max(stats.max_ply_evaluations, helix.evaluations);
    }

    // Fallback: a ply whose crossing did not converge is taken as the circular method sees it,
    // at the tube hit's cross-section (with the frame there, which `at` lacks).
    if (found.unconverged != 0) {
        CentrelineProjection framed = at;
        framed.point = frames.evaluate(at.segment, at.t);
        for (int ply = 0; ply < m.plies; ++ply) {
            if (!(found.unconverged >> ply & 1)) continue;
            Candidate cand{ply, cut_at(framed, q.yarn, q.twist, ply)};
            Vec3 normal;
            if (!circular_cut_hit(hit, framed, cand.cut.centre, cand.enter, normal)) continue;
            crossed_mask |= 1u << ply;
            if (!hit_found || cand.enter < best.enter) best = cand;
            hit_found = true;
        }
    }

    PlyHit h = hit_found ? finish_hit(best, hit.point + hit.direction * std::max(best.enter, 0.0f), q.twist, hit)
                         : stretch.exit_distance >= 0 ? pass_through(hit, stretch.exit_distance)
                                                      : pass_through(frames, hit, at);
    if (hit_found) h.plies_crossed = __builtin_popcount(crossed_mask);
    stats.evaluations = evaluations;
    stats.converged = found.unconverged == 0;
    return h;
}

}  // namespace purl::plies
