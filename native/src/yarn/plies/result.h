// What every ply search method shares: a ply's cut at one cross-section of the yarn, the
// candidate hit, and the PlyHit (or pass-through) made from it.
#pragma once
#include <algorithm>
#include <cstdint>

#include "math/ray_cylinder.h"
#include "yarn/implicit_plies.h"

namespace purl::plies {

// A ray passing this close (in tolerances) outside a ply still touches it: the explicit
// reference counts a hit within 1e-5 R of the surface.
constexpr float kGraze = 0.1f;

// Plies padded to a multiple of 4, the width of the methods' vectorised loops over plies
// (the padding lanes repeat a real ply; their results are never read).
inline int padded_plies(int plies) { return (plies + 3) & ~3; }
static_assert(kMaxPlies % 4 == 0, "the scan grids pad plies to a multiple of 4");

// Fixed-size scratch arrays left uninitialized: a query's arrays hold kilobytes of CurvePoints
// whose default member initializers would otherwise be zeroed on every query (a measurable
// share of a side-view query). Only trivially copyable aggregates are stored.
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

// (segment, t) of the unwrapped parameter g.
void locate(const CachedCurve& frames, double g, uint32_t& segment, float& t);
PlyCut cut_at(const CachedCurve& frames, const YarnDescription& d, const YarnTwist& tw, int ply, double g);
// At the cross-section of a centre-line projection (with its frame).
inline PlyCut cut_at(const CentrelineProjection& at, const YarnDescription& d, const YarnTwist& tw, int ply) {
    PlyCut cut;
    cut.g = at.segment + double(at.t);
    cut.segment = at.segment;
    cut.t = at.t;
    cut.yarn = at.point;
    cut.centre = ply_centre(at.point, d, tw, ply);
    return cut;
}

// Newton step (m of yarn) toward the point of a ply centre-line closest to x: the root of
// (P - x).P', with derivative |P'|^2 + (P - x).P'' (kept from falling below a quarter of
// |P'|^2, where the distance has no minimum nearby).
inline float closest_point_step(Vec3 position, Vec3 d1, Vec3 d2, Vec3 x) {
    const Vec3 w = position - x;
    const float slope = dot(d1, d1) + dot(w, d2);
    return -dot(w, d1) / std::max(slope, 0.25f * dot(d1, d1));
}

struct Candidate {
    int ply = 0;
    PlyCut cut;
    float enter = 0;             // ray distance of the entry from the tube entry, m
    float approach = 0;          // ray distance of the closest approach to the ply centre-line, m
};

// The ply surface point, frame and coordinates for a hit at `point`.
PlyHit finish_hit(const Candidate& c, Vec3 point, const YarnTwist& tw, const YarnTubeHit& hit);

// A ray that passes between the plies, leaving the tube `exit_distance` after its entry.
PlyHit pass_through(const YarnTubeHit& hit, float exit_distance);
// The same, the exit searched from the centre-line parameter (segment, t) near the entry.
PlyHit pass_through(const CurveFrames& frames, const YarnTubeHit& hit, uint32_t segment, float t);
// The same when `at` is the projection of the tube entry itself (not of a neighbouring point).
template <class Curve>  // CurveFrames, or a query's CachedCurve
PlyHit pass_through(const Curve& frames, const YarnTubeHit& hit, const CentrelineProjection& at) {
    return pass_through(hit, tube_exit(frames, at, hit.point, hit.direction).distance);
}

// The ray's entry into and exit from a ply's straight cylinder (ray distances from `origin`);
// false when it misses. A ray along the cylinder is inside all along or not at all.
bool cross_ply_cylinder(Vec3 origin, Vec3 direction, Vec3 point, Vec3 axis, float radius, float& enter,
                        float& leave);

}  // namespace purl::plies
