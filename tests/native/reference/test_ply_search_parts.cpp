// The ply search's hand-vectorised copies agree with the scalar code they copy: the exact
// method's scan grid with YarnModel::ply and sample(), the local method's scan grid and scan
// nodes with its helices. The copies share their formulas (one function each); these tests
// catch a change to the loops around them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/ply_validation.h"
#include "yarn/plies/exact_scan.h"
#include "yarn/plies/local_helices.h"

namespace purl {
namespace {

using namespace plies;

// |a - b| within `relative` of the larger of `scale` and |b|.
void expect_close(float a, float b, float scale, float relative, const char* what) {
    EXPECT_NEAR(a, b, relative * std::max(scale, std::fabs(b))) << what;
}

// A tight loop (curvature radius 2 R), where the model's pieces bend and turn.
struct Loop {
    std::vector<Vec4> points = validation_curve(2.0f);
    CurveFrames frames{CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), true)};
};

TEST(PlySearchParts, ExactScanGridMatchesThePlyModel) {
    const Loop loop;
    const CachedCurve curve(loop.frames);
    for (int plies : {1, 3, 5, 12}) {
        const YarnDescription d = touching_plies(plies);
        const YarnTwist tw = yarn_twist(loop.frames, d);
        const CurvePoint c0 = curve.evaluate(3, 0.2f), c1 = curve.evaluate(3, 0.9f);
        // The model seen by an oblique ray entering near c0.
        YarnModel m;
        m.origin = c0.position + c0.normal * 0.9f;
        m.ez = normalize(c0.normal * -1.0f + c0.tangent * 0.6f);
        m.ex = normalize(cross(m.ez, c0.tangent));
        m.ey = cross(m.ez, m.ex);
        m.distance = d.ply_distance;
        m.ply_radius = d.ply_radius;
        m.rate = tw.ply_rate;
        m.plies = plies;
        m.cos_offset = ply_offsets().cos[plies];
        m.sin_offset = ply_offsets().sin[plies];
        m.pieces = 1;
        m.built_lo = m.built_hi = 0;
        Knot a, b;
        make_knot(c0, 3.2, 0.0f, m, a);
        make_knot(c1, 3.9, c1.arc_length - c0.arc_length, m, b);
        make_piece(a, b, m, m.piece[0]);
        const Piece& q = m.piece[0];
        float cp[kMaxPlies], sp[kMaxPlies];
        for (int i = 0; i < kMaxPlies; ++i) cp[i] = m.cos_offset[i < plies ? i : 0], sp[i] = m.sin_offset[i < plies ? i : 0];
        PieceGrid grid;
        grid.set(q, cp, sp, plies);
        for (float v : {0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
            grid.node(plies, v, q.inv_h, 1);
            for (int i = 0; i < plies; ++i) {
                PlyPoly poly;
                m.ply(i, 0, poly);
                const Sampled o = sample(poly, q.s0 + v * q.h);
                const float scale = sqr(d.ply_distance * c0.radius);  // D's size; f and f' follow
                expect_close(grid.D[1][i], o.D, scale, 1e-4f, "D");
                expect_close(grid.f[1][i], o.f, scale * q.inv_h, 1e-4f, "f");
                expect_close(grid.slope[1][i], o.slope, scale * q.inv_h * q.inv_h, 1e-4f, "slope");
            }
        }
    }
}

TEST(PlySearchParts, LocalScanNodesMatchTheHelices) {
    const Loop loop;
    const CurvePoint c = loop.frames.evaluate(5, 0.4f);
    const Vec3 ray = normalize(c.normal * -1.0f + c.binormal * 0.3f + c.tangent * 0.8f);
    const Vec3 entry = c.position + c.normal * 0.95f * c.radius;
    for (int plies : {1, 3, 5, 12}) {
        const YarnDescription d = touching_plies(plies);
        const YarnTwist tw = yarn_twist(loop.frames, d);
        LocalHelices m;
        m.world = {c.position - entry, c.tangent, c.curvature, c.normal, c.binormal};
        m.ray = ray;
        m.nk = dot(c.normal, c.curvature);
        m.bk = dot(c.binormal, c.curvature);
        m.offset = d.ply_distance * c.radius;
        m.ply_radius = d.ply_radius * c.radius;
        m.rate = tw.ply_rate;
        m.phase = ply_phase(tw, c.arc_length);
        m.set_offsets(plies);
        m.set_across(normalize(cross(c.tangent, ray)));
        LocalGrid grid;
        grid.build(m, plies, -2.0f * c.radius, 3.0f * c.radius, 20);
        for (int k = 0; k <= grid.steps; ++k)
            for (int i = 0; i < plies; ++i) {
                // The vectorised grid against the scalar node ...
                const LocalNode a = grid.node(k, i), b = local_node(m, i, grid.s[k]);
                const float r = c.radius;
                expect_close(a.f, b.f, r, 1e-5f, "grid f");
                expect_close(a.miss, b.miss, r, 1e-5f, "grid miss");
                expect_close(a.pace, b.pace, 1, 1e-5f, "grid pace");
                // ... and the node, seen across the ray, against the helix in world space.
                Vec3 w, w1;
                m.at(i, grid.s[k], w, w1, nullptr);
                const float w1z = dot(w1, ray);
                expect_close(b.f, m.crossing(w, w1), r, 1e-5f, "node f");
                expect_close(b.miss, std::sqrt(m.miss2(w)), r, 1e-5f, "node miss");
                expect_close(b.pace, std::sqrt(dot(w1, w1) - w1z * w1z), 1, 1e-5f, "node pace");
            }
    }
}

}  // namespace
}  // namespace purl
