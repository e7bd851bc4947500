#include "yarn/plies/exact_search.h"

#include <algorithm>
#include <cmath>

namespace purl::plies {
namespace {

// The ply's model at arc length s, moving q to the built piece that holds s (the end pieces of
// what is built extrapolate).
ModelPoint model_at(const YarnModel& m, int ply, PlyPoly& q, float s) {
    for (int hop = 0; hop < kMaxPieces; ++hop) {
        const float v = (s - q.s0) * q.inv_h;
        if (v < 0 && q.piece > m.built_lo) m.ply(ply, q.piece - 1, q);
        else if (v > 1 && q.piece < m.built_hi) m.ply(ply, q.piece + 1, q);
        else break;
    }
    return q.at(s);
}

// The model's estimate of where the ray enters a ply near a crossing.
struct ModelEntry {
    float enter;          // ray distance from the tube entry, m
    float cos_incidence;  // of the ray on the ply surface there
    bool trusted;         // false when the entry moved too far past the built pieces for the model
};

// The ray's entry into the ply near a crossing, on the model: the cylinder along the tangent
// there, moved to the cylinder at the helix point closest to the entry (what the exact method
// then does on the curve). `s` ends at the helix point nearest the entry, in piece q.piece;
// when the entry is not trusted, `s` stays at the crossing (the exact refinement's start).
ModelEntry model_entry(const YarnModel& m, int ply, PlyPoly& q, float approach, float tolerance, int refinements,
                       float max_shift, float& s) {
    const float crossing = s;
    const int start_piece = q.piece;
    ModelPoint p = q.at(s);
    const Vec3 o(0.0f), z(0, 0, 1);
    float enter, leave;
    bool hits = cross_ply_cylinder(o, z, p.p, normalize(p.d), p.ply_radius, enter, leave);
    float lambda = hits ? clamp(enter, 0.0f, approach) : approach;
    for (int r = 0; r < refinements; ++r) {
        const float ds = clamp(closest_point_step(p.p, p.d, p.dd, z * lambda), -max_shift, max_shift);
        if (hits && std::fabs(ds) < tolerance) break;
        s += ds;
        p = model_at(m, ply, q, s);
        hits = cross_ply_cylinder(o, z, p.p, normalize(p.d), p.ply_radius, enter, leave);
        if (!hits) break;
        lambda = clamp(enter, 0.0f, approach);
        if (std::fabs(ds) < tolerance) break;
    }
    ModelEntry e;
    const float v = (s - q.s0) * q.inv_h;
    e.trusted = v > -0.25f && v < 1.25f;
    if (!e.trusted) {  // back to the crossing's piece, rebuilt (rare) rather than copied (every entry)
        s = crossing;
        if (q.piece != start_piece) m.ply(ply, start_piece, q);
    }
    const Vec3 axis = normalize(p.d);
    Vec3 radial = z * lambda - p.p;
    radial -= axis * dot(radial, axis);
    const float len = length(radial);
    e.cos_incidence = len > 1e-12f ? std::fabs(radial.z) / len : 1.0f;
    e.enter = lambda;
    return e;
}

}  // namespace

const Knot& Knots::operator()(int j, const YarnModel& m, int& evaluations) {
    if (evaluated_ >> j & 1) return knots_[j];
    const double g = stretch_.g_lo + (stretch_.g_hi - stretch_.g_lo) * j / pieces_;
    uint32_t segment;
    float t;
    locate(frames_, g, segment, t);
    const CurvePoint k = frames_.evaluate(segment, t);
    ++evaluations;
    if (evaluated_ == 0) s_origin_ = k.arc_length;
    // Arc length continuous across a loop's seam, from an evaluated neighbour.
    float s = k.arc_length - s_origin_;
    const float total = frames_.frames().total_length();
    if (frames_.closed() && j > 0 && (evaluated_ >> (j - 1) & 1))
        while (s < knots_[j - 1].s) s += total;
    else if (frames_.closed() && j < pieces_ && (evaluated_ >> (j + 1) & 1))
        while (s > knots_[j + 1].s) s -= total;
    make_knot(k, g, s, m, knots_[j]);
    evaluated_ |= uint64_t(1) << j;
    return knots_[j];
}

namespace {

// Pieces of at most model_turn radians of ply turn and model_length yarn radii.
int piece_count(const Stretch& stretch, float radius, const YarnTwist& tw, const PlyTraceOptions& options) {
    const float per_piece = std::min(options.model_turn / std::max(std::fabs(tw.ply_rate), 1e-30f),
                                     options.model_length * radius);
    return std::min(kMaxPieces, 1 + static_cast<int>((stretch.s_hi - stretch.s_lo) / per_piece));
}

}  // namespace

ModelSearch::ModelSearch(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw,
                         const YarnTubeHit& hit, const Stretch& stretch, float radius, const PlyTraceOptions& options,
                         Vec3 across, bool forward)
    : d_(d), stretch_(stretch), options_(options), forward_(forward),
      knots_(frames, stretch, piece_count(stretch, radius, tw, options)) {
    m_.origin = hit.point;
    m_.ez = hit.direction;
    m_.ex = across;
    m_.ey = cross(m_.ez, m_.ex);
    m_.distance = d.ply_distance;
    m_.ply_radius = d.ply_radius;
    m_.rate = tw.ply_rate;
    m_.plies = std::min(std::max(1, d.plies()), kMaxPlies);
    m_.cos_offset = ply_offsets().cos[m_.plies];
    m_.sin_offset = ply_offsets().sin[m_.plies];
    m_.pieces = knots_.pieces();
    tolerance_ = options.tolerance * radius;
    slack_ = options.model_margin * radius + tolerance_;
    brackets_.polys = &polys_;
    for (int i = 0; i < kMaxPlies; ++i) {
        grid_cos_[i] = m_.cos_offset[i < m_.plies ? i : 0];
        grid_sin_[i] = m_.sin_offset[i < m_.plies ? i : 0];
    }
}

void ModelSearch::run(ModelCrossings& out) {
    for (int n = 0; n < m_.pieces; ++n)
        if (!scan_piece(forward_ ? n : m_.pieces - 1 - n, out)) break;
}

// Builds piece j and finds its crossings; false when no later piece can matter.
bool ModelSearch::scan_piece(int j, ModelCrossings& out) {
    make_piece(knots_(j, m_, out.evaluations), knots_(j + 1, m_, out.evaluations), m_, m_.piece[j]);
    m_.built_lo = std::min(m_.built_lo, j);
    m_.built_hi = std::max(m_.built_hi, j);
    const Piece& q = m_.piece[j];
    // No entry into a ply near a helix point of this piece comes before this ray distance:
    // the helix stays within a ply distance of the centre-line, which bulges at most
    // h^2 kappa / 8.
    const float a_max = d_.ply_distance * std::max(q.r0, q.r1), r_max = d_.ply_radius * std::max(q.r0, q.r1);
    const float earliest =
        std::min(knots_[j].c.z, knots_[j + 1].c.z) - 1.25f * q.h * q.h * q.kappa / 8 - a_max - r_max - slack_;
    // Late: entries near this piece cannot win. A ply still within reach where the previous
    // piece ended may enter back there, so it is not late; the others only matter for N_i.
    const uint32_t late = earliest > best_bound_ ? ~continuing_ : 0u;
    const uint32_t all = (1u << m_.plies) - 1;
    if ((late & all) == all && out.sure == all) return false;
    polys_.reset(m_, j);
    brackets_.bound(m_, q);
    brackets_.reach2 = sqr(r_max + slack_);
    brackets_.count = 0;
    scan_grid(q, late, sqr(std::max(d_.ply_radius * std::min(q.r0, q.r1) - slack_, 0.0f)), out);
    const int first = out.count;
    for (int w = 0; w < brackets_.count && out.count < kMaxWork; ++w) add_crossing(brackets_.work[w], j, out);
    add_entries(out, first, late);
    return true;
}

// Every ply at the piece's grid nodes; intervals that may hold a crossing become work. Also
// notes which plies are within reach where the next piece in ray order begins.
void ModelSearch::scan_grid(const Piece& q, uint32_t late, float sure2, ModelCrossings& out) {
    grid_.set(q, grid_cos_, grid_sin_, m_.plies);
    float s_prev = q.s0;
    int prev = 0;
    grid_.node(m_.plies, 0, q.inv_h, prev);
    const float reach2 = brackets_.reach2;
    uint32_t start_reach = 0;
    for (int i = 0; i < m_.plies; ++i) start_reach |= uint32_t(grid_.D[prev][i] <= reach2) << i;
    for (int k = 1; k <= kSubsteps; ++k) {
        const int next = prev ^ 1;
        const float s_next = q.s0 + q.h * k / kSubsteps;
        grid_.node(m_.plies, float(k) / kSubsteps, q.inv_h, next);
        const float *D0 = grid_.D[prev], *f0 = grid_.f[prev], *slope0 = grid_.slope[prev];
        const float *D1 = grid_.D[next], *f1 = grid_.f[next], *slope1 = grid_.slope[next];
        for (int i = 0; i < m_.plies; ++i) {
            if (out_of_reach(s_prev, D0[i], s_next, D1[i], reach2, brackets_.speed, brackets_.accel)) continue;
            if (late >> i & 1) {
                if (out.sure >> i & 1) continue;
                // A closest approach bracketed with an end this close to the ray: crossed,
                // without solving for where.
                if (f0[i] < 0 && f1[i] >= 0 && std::min(D0[i], D1[i]) < sure2) {
                    out.sure |= 1u << i;
                    continue;
                }
            }
            brackets_.interval(i, {s_prev, D0[i], f0[i], slope0[i]}, {s_next, D1[i], f1[i], slope1[i]}, 0);
        }
        s_prev = s_next;
        prev = next;
    }
    uint32_t end_reach = 0;
    for (int i = 0; i < m_.plies; ++i) end_reach |= uint32_t(grid_.D[prev][i] <= reach2) << i;
    continuing_ = forward_ ? end_reach : start_reach;
}

// One bracketed crossing solved on the model, kept if within reach.
void ModelSearch::add_crossing(const Work& wk, int j, ModelCrossings& out) {
    ModelCandidate mc;
    mc.ply = wk.ply;
    mc.piece = j;
    mc.s_lo = wk.lo.s;
    mc.s_hi = wk.hi.s;
    if (!solve(polys_[wk.ply], wk, tolerance_, options_.max_iterations, mc.s_cross)) {
        out.unconverged |= 1u << wk.ply;
        return;
    }
    const ModelPoint p = polys_[wk.ply].at(mc.s_cross);
    mc.approach = p.p.z;
    mc.s_enter = mc.s_cross;
    mc.piece_enter = j;
    mc.enter = kNoEntry;  // entries come later, where they matter
    mc.slack = 0;
    const float miss = std::sqrt(p.p.x * p.p.x + p.p.y * p.p.y);
    if (miss > p.ply_radius + slack_) return;  // passes beside the ply
    mc.ambiguous = miss > p.ply_radius - slack_;
    mc.miss = miss - p.ply_radius;
    if (!mc.ambiguous) out.sure |= 1u << wk.ply;
    out.items[out.count++] = mc;
}

// Model entries of the candidates from `first` on, except those of late plies.
void ModelSearch::add_entries(ModelCrossings& out, int first, uint32_t late) {
    for (int i = first; i < out.count; ++i) {
        ModelCandidate& mc = out.items[i];
        if (late >> mc.ply & 1) continue;
        PlyPoly at_entry = polys_[mc.ply];
        const ModelEntry e = model_entry(m_, mc.ply, at_entry, std::max(mc.approach, 0.0f), tolerance_,
                                         options_.refinements, shift(), mc.s_enter);
        mc.enter = e.enter;
        mc.piece_enter = at_entry.piece;
        // An entry the model cannot vouch for is refined whatever its estimate.
        mc.slack = e.trusted ? slack_ / std::max(e.cos_incidence, 0.05f) + tolerance_ : kNoEntry;
        if (!mc.ambiguous) best_bound_ = std::min(best_bound_, mc.enter + mc.slack);
    }
}

}  // namespace purl::plies
