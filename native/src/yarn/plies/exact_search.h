// The exact method's search on its model: pieces of the model built lazily, in the order the
// ray meets them, each scanned for every ply's crossings (exact_scan.h), with the model's own
// estimate of where the ray enters the ply; a search that has every ply crossed and an entry
// no later piece can beat stops early. What it finds is settled on the exact curve (exact.cpp).
#pragma once
#include "yarn/plies/exact_scan.h"
#include "yarn/plies/stretch.h"

namespace purl::plies {

// A crossing found on the model, with where the ray enters the ply there (model estimates).
struct ModelCandidate {
    int ply, piece, piece_enter;  // pieces of the crossing and of the entry
    float s_cross, s_enter;  // model arc lengths of the crossing and of the helix point nearest the entry
    float s_lo, s_hi;        // the crossing's bracket
    float approach, enter;   // ray distances of the closest approach and of the entry, m
    float slack;             // how much earlier the exact entry could be, m
    float miss;              // model miss distance less the ply radius, m
    bool ambiguous;          // the miss distance is within the model's margin of the ply radius
};

// What the search found. Sets of plies are bit masks (bit i: ply i).
struct ModelCrossings {
    Slots<ModelCandidate, kMaxWork> items;
    int count = 0;
    uint32_t sure = 0;         // plies crossed by the model's margin
    uint32_t unconverged = 0;  // plies with a crossing the model's Newton steps did not settle
    int evaluations = 0;       // exact frames evaluated for the knots
};

// The exact frames at the knots, evenly spaced in curve parameter over the stretch, each
// evaluated when a piece first needs it.
class Knots {
public:
    Knots(const CachedCurve& frames, const Stretch& stretch, int pieces) : frames_(frames), stretch_(stretch), pieces_(pieces) {}
    const Knot& operator()(int j, const YarnModel& m, int& evaluations);
    const Knot& operator[](int j) const { return knots_[j]; }  // one already evaluated
    int pieces() const { return pieces_; }

private:
    const CachedCurve& frames_;
    const Stretch& stretch_;
    int pieces_;
    uint64_t evaluated_ = 0;  // bit j: knot j is set
    float s_origin_ = 0;      // arc length of the first knot evaluated
    Slots<Knot, kMaxPieces + 1> knots_;
};

class ModelSearch {
public:
    // across: the cutting plane's normal (across the ray and the yarn); forward: the ray runs
    // toward larger arc length.
    ModelSearch(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, const YarnTubeHit& hit,
                const Stretch& stretch, float radius, const PlyTraceOptions& options, Vec3 across, bool forward);
    void run(ModelCrossings& out);

    const YarnModel& model() const { return m_; }
    float tolerance() const { return tolerance_; }  // m
    float shift() const { return stretch_.s_hi - stretch_.s_lo; }  // the longest step along the yarn, m

private:
    bool scan_piece(int j, ModelCrossings& out);
    void scan_grid(const Piece& q, uint32_t late, float sure2, ModelCrossings& out);
    void add_crossing(const Work& wk, int j, ModelCrossings& out);
    void add_entries(ModelCrossings& out, int first, uint32_t late);

    static constexpr float kNoEntry = 1e30f;
    const YarnDescription& d_;
    const Stretch& stretch_;
    const PlyTraceOptions& options_;
    const bool forward_;
    Knots knots_;
    float tolerance_ = 0, slack_ = 0;  // m: Newton's tolerance; the model's margin plus it
    YarnModel m_;
    Brackets brackets_;
    PiecePlies polys_;
    float grid_cos_[kMaxPlies], grid_sin_[kMaxPlies];  // every ply's offset, padded with ply 0's
    PieceGrid grid_;  // left uninitialized: filled per piece
    // Carried from piece to piece in ray order:
    float best_bound_ = kNoEntry;  // no exact entry can come later than this
    uint32_t continuing_ = 0;      // plies within reach where the next piece begins
};

}  // namespace purl::plies
