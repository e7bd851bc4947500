#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/explicit_plies.h"
#include "reference/ply_validation.h"
#include "yarn/implicit_plies.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

// A straight yarn along +z of the given radius, 40 radii long.
struct StraightYarn {
    std::vector<Vec4> points;
    CurveFrames frames;
    explicit StraightYarn(float radius = 1.0f) : points(make(radius)), frames(CurveView::chain(points.data(), 40, false)) {}
    static std::vector<Vec4> make(float radius) {
        std::vector<Vec4> p;
        for (int i = 0; i < 40; ++i) p.emplace_back(0.0f, 0.0f, radius * i, radius);
        return p;
    }
};

// The tube entry of a ray from +x toward -x at height y, tilted by psi toward +z, aimed at z0.
YarnTubeHit side_hit(const CurveFrames& f, float y, float psi, float z0, float radius = 1.0f) {
    YarnTubeHit h;
    h.direction = normalize(Vec3(-std::cos(psi), 0, std::sin(psi)));
    const float x = std::sqrt(radius * radius - y * y);
    h.point = Vec3(x, y, z0);
    h.origin = h.point - h.direction * 10.0f * radius;
    const CentrelineProjection p = project_to_centreline(f, h.point, static_cast<uint32_t>(z0 / radius), 0.5f);
    h.segment = p.segment;
    h.t = p.t;
    return h;
}

// One query, the yarn's twist computed here.
PlyHit trace(const CurveFrames& f, const YarnDescription& d, const YarnTubeHit& h, const PlyTraceOptions& o = {},
             PlySearchStats* spent = nullptr) {
    const YarnTwist tw = yarn_twist(f, d);
    return trace_plies({f, d, tw, h}, o, spent);
}

bool finite(const PlyHit& h) {
    return is_finite(h.point) && is_finite(h.normal) && is_finite(h.tangent) && std::isfinite(h.distance) &&
           std::isfinite(h.exit_distance) && std::isfinite(h.u_ply) && std::isfinite(h.v_ply) &&
           std::isfinite(h.arrangement_azimuth);
}

TEST(YarnTube, ProjectionAndChordOnAStraightTube) {
    const StraightYarn y;
    const CentrelineProjection p = project_to_centreline(y.frames, Vec3(0.3f, 0.4f, 17.25f), 10, 0.9f);
    EXPECT_TRUE(p.converged);
    EXPECT_NEAR(p.point.position.z, 17.25f, 1e-4f);
    EXPECT_NEAR(p.distance, 0.5f, 1e-5f);
    // A chord at height h tilted by psi: 2 sqrt(1 - h^2) / cos(psi).
    for (float psi : {0.0f, 0.5f, 1.2f}) {
        const YarnTubeHit h = side_hit(y.frames, 0.6f, psi, 18.0f);
        EXPECT_NEAR(tube_chord_length(y.frames, h.segment, h.t, h.point, h.direction), 1.6f / std::cos(psi), 1e-3f)
            << psi;
    }
    // Along the axis the chord runs to the end of the yarn; leaving at once is 0; never NaN.
    const float along = tube_chord_length(y.frames, 5, 0.5f, Vec3(0, 0, 6.5f), Vec3(0, 0, 1));
    EXPECT_TRUE(std::isfinite(along));
    EXPECT_GT(along, 20.0f);
    EXPECT_NEAR(tube_chord_length(y.frames, 5, 0.5f, Vec3(1, 0, 6.5f), Vec3(1, 0, 0)), 0, 1e-4f);
}

TEST(YarnTube, ChordOnATightBendMatchesTheExplicitTube) {
    const std::vector<Vec4> pts = validation_curve(2.0f);
    const CurveFrames f(CurveView::chain(pts.data(), static_cast<uint32_t>(pts.size()), true));
    const ExplicitPlies ex(f, touching_plies(3));
    int compared = 0;
    for (int i = 0; i < 40; ++i) {
        // Rays from above and from the side, grazing along the bend.
        const float a = 0.3f * i;
        const Vec3 target(2 * std::cos(a), 2 * std::sin(a), 0.0f);
        const Vec3 dir = normalize(Vec3(-std::sin(a + 0.4f), std::cos(a + 0.4f), i % 2 ? -0.6f : -0.2f));
        const Vec3 origin = target - dir * 8.0f + Vec3(0, 0, 0.3f);
        const ExplicitHit tube = ex.intersect_tube(origin, dir, 0, 20);
        if (!tube.hit) continue;
        const float exit = ex.tube_exit(origin, dir, tube.distance + 1e-4f, 20, tube.segment, tube.t);
        const float chord = tube_chord_length(f, tube.segment, tube.t, tube.point, dir);
        EXPECT_NEAR(chord, exit - tube.distance, 2e-3f) << i;
        ++compared;
    }
    EXPECT_GT(compared, 20);
}

TEST(ImplicitPlies, SideViewMatchesTheExplicitPliesExactly) {
    const StraightYarn y;
    const YarnDescription d = touching_plies(3);
    const ExplicitPlies ex(y.frames, d);
    for (float offset : {-0.8f, -0.3f, 0.0f, 0.45f, 0.9f}) {
        const YarnTubeHit h = side_hit(y.frames, offset, 0.0f, 20.3f);
        PlySearchStats spent;
        const PlyHit imp = trace(y.frames, d, h, {}, &spent);
        const ExplicitHit ref = ex.intersect_plies(h.origin, h.direction, 0, 20);
        ASSERT_EQ(imp.hit, ref.hit) << offset;
        EXPECT_TRUE(spent.converged);
        EXPECT_TRUE(finite(imp));
        if (!ref.hit) continue;
        EXPECT_EQ(imp.ply, ref.ply);
        EXPECT_NEAR(length(imp.point - ref.point), 0, 1e-3f);
        EXPECT_GT(dot(imp.normal, ref.normal), std::cos(0.2f * kPi / 180));
        EXPECT_GT(dot(imp.tangent, ref.tangent), std::cos(0.2f * kPi / 180));
        // The ply frame: normal perpendicular to the tangent, facing the ray.
        EXPECT_NEAR(dot(imp.normal, imp.tangent), 0, 1e-4f);
        EXPECT_LT(dot(imp.normal, h.direction), 0.0f);
        EXPECT_GE(imp.plies_crossed, 1);
        EXPECT_GE(imp.u_ply, 0.0f);
        EXPECT_LT(imp.u_ply, 2 * kPi);
    }
}

TEST(ImplicitPlies, RimRayPassesThroughWithItsExitDistance) {
    // Plies fill 97% of the radius: a ray at 0.985 R crosses the tube beside all of them.
    const StraightYarn y;
    const YarnTubeHit h = side_hit(y.frames, 0.985f, 0.3f, 20.0f);
    for (PlyCrossSection cs : {PlyCrossSection::elliptical, PlyCrossSection::circular}) {
        PlyTraceOptions o;
        o.cross_section = cs;
        const PlyHit imp = trace(y.frames, touching_plies(3), h, o);
        EXPECT_FALSE(imp.hit);
        EXPECT_EQ(imp.plies_crossed, 0);
        EXPECT_NEAR(imp.exit_distance, 2 * std::sqrt(1 - 0.985f * 0.985f) / std::cos(0.3f), 1e-3f);
        EXPECT_TRUE(finite(imp));
    }
}

TEST(ImplicitPlies, UnconvergedSearchFallsBackToTheCircularCut) {
    // No Newton steps allowed: a ply whose start is not already within tolerance falls back
    // to the tube hit's cross-section; the result is flagged and still a finite ply hit. (On a
    // straight yarn the model is exact, so a start inside a grid interval can already be within
    // the default tolerance; a tighter one makes the fallback the rule.)
    const StraightYarn y;
    const YarnDescription d = touching_plies(5);
    PlyTraceOptions starved;
    starved.max_iterations = 0;
    starved.tolerance = 1e-6f;
    int hits = 0, unconverged = 0;
    for (int i = 0; i < 50; ++i) {
        const YarnTubeHit h = side_hit(y.frames, -0.9f + 0.036f * i, 1.0f, 20.0f);
        PlySearchStats spent;
        const PlyHit imp = trace(y.frames, d, h, starved, &spent);
        unconverged += !spent.converged;
        EXPECT_TRUE(finite(imp));
        hits += imp.hit;
        if (imp.hit) {
            EXPECT_NEAR(length(imp.normal), 1, 1e-4f);
            EXPECT_NEAR(length(imp.tangent), 1, 1e-4f);
        }
    }
    EXPECT_GT(unconverged, 40);
    EXPECT_GT(hits, 25);  // the fallback still finds plies
    // With the default budget the same rays converge.
    PlySearchStats spent;
    trace(y.frames, d, side_hit(y.frames, 0.1f, 1.0f, 20.0f), {}, &spent);
    EXPECT_TRUE(spent.converged);
}

TEST(ImplicitPlies, DegenerateRaysStayFinite) {
    const StraightYarn y;
    const YarnDescription d = touching_plies(3);
    YarnTubeHit h;
    h.direction = Vec3(0, 0, 1);  // straight down the yarn
    h.point = Vec3(0.999f, 0, 10);
    h.origin = h.point - h.direction;
    h.segment = 9;
    h.t = 0.5f;
    for (PlyCrossSection cs : {PlyCrossSection::elliptical, PlyCrossSection::circular}) {
        PlyTraceOptions o;
        o.cross_section = cs;
        const PlyHit imp = trace(y.frames, d, h, o);
        EXPECT_TRUE(finite(imp));
        EXPECT_FALSE(imp.hit);
    }
    // A hit point well off the tube (a sloppy caller) still gives a finite answer.
    h.direction = normalize(Vec3(-1, 0.2f, 0.3f));
    h.point = Vec3(3, 0, 10);
    EXPECT_TRUE(finite(trace(y.frames, d, h)));
}

TEST(ImplicitPlies, ScaleFree) {
    // The same view of a yarn a thousand times thinner gives the same plies and frames.
    const StraightYarn big(1.0f), small(1e-3f);
    const YarnDescription d = touching_plies(5);
    for (float offset : {-0.7f, 0.2f, 0.6f}) {
        const PlyHit a = trace(big.frames, d, side_hit(big.frames, offset, 0.9f, 20.2f));
        const PlyHit b = trace(small.frames, d, side_hit(small.frames, offset * 1e-3f, 0.9f, 20.2e-3f, 1e-3f));
        ASSERT_EQ(a.hit, b.hit);
        if (!a.hit) continue;
        EXPECT_EQ(a.ply, b.ply);
        EXPECT_NEAR(a.distance * 1e-3f, b.distance, 1e-6f);
        EXPECT_GT(dot(a.normal, b.normal), 0.9999f);
        EXPECT_GT(dot(a.tangent, b.tangent), 0.9999f);
        EXPECT_NEAR(a.u_ply, b.u_ply, 1e-3f);
        EXPECT_NEAR(a.v_ply * 1e-3f, b.v_ply, 1e-6f);
    }
}

TEST(ImplicitPlies, PliesCloseOnThemselvesAroundALoop) {
    // Ply twist is rounded to whole turns per loop, so every ply meets itself at the seam.
    const std::vector<Vec4> pts = validation_curve(3.0f);
    const CurveFrames f(CurveView::chain(pts.data(), static_cast<uint32_t>(pts.size()), true));
    const YarnDescription d = touching_plies(3);
    const YarnTwist tw = yarn_twist(f, d);
    EXPECT_NEAR(std::remainder(tw.ply_rate * f.total_length(), 2 * kPi), 0, 1e-3f);
    EXPECT_NEAR(tw.ply_rate, d.ply_twist / f.reference_radius(), 0.5f * kPi / f.total_length() + 1e-6f);
    const uint32_t last = f.segment_count() - 1;
    for (int ply = 0; ply < 3; ++ply) {
        const PlyCentre a = ply_centre(f.evaluate(last, 1.0f), d, tw, ply);
        const PlyCentre b = ply_centre(f.evaluate(0, 0.0f), d, tw, ply);
        EXPECT_NEAR(length(a.position - b.position), 0, 1e-3f) << ply;
    }
}

TEST(ImplicitPlies, HelixDerivativesMatchFiniteDifferences) {
    // The analytic dP/ds and d2P/ds2 drive the Newton steps: check them on a tight bend.
    const std::vector<Vec4> pts = validation_curve(2.0f);
    const CurveFrames f(CurveView::chain(pts.data(), static_cast<uint32_t>(pts.size()), true));
    const YarnDescription d = touching_plies(2);
    const YarnTwist tw = yarn_twist(f, d);
    const float h = 0.05f;  // in t; smaller steps drown the second difference in float noise
    for (uint32_t seg : {1u, 9u, 17u}) {
        const CurvePoint c0 = f.evaluate(seg, 0.5f - h), c1 = f.evaluate(seg, 0.5f), c2 = f.evaluate(seg, 0.5f + h);
        const PlyCentre p0 = ply_centre(c0, d, tw, 1), p1 = ply_centre(c1, d, tw, 1), p2 = ply_centre(c2, d, tw, 1);
        const float ds = 0.5f * (c2.arc_length - c0.arc_length);
        const Vec3 d1 = (p2.position - p0.position) / (2 * ds);
        const Vec3 d2 = (p2.position - p1.position * 2.0f + p0.position) / (ds * ds);
        EXPECT_NEAR(length(d1 - p1.derivative), 0, 0.01f * length(d1));
        EXPECT_NEAR(length(d2 - p1.second_derivative), 0, 0.05f * length(d2));
    }
}

TEST(ImplicitPlies, HelixTangentFollowsTheStoredFrameOnANonPlanarCurve) {
    // A coarse trefoil, where the interpolated frame turns about the tangent and the Hermite
    // arc length is not the true one: the ply tangent (the shading frame's) must still be the
    // derivative of the helix as built on that frame. Cloth is non-planar everywhere.
    std::vector<Vec4> pts;
    for (int i = 0; i < 15; ++i) {
        const float a = 2 * kPi * (i % 12) / 12;
        pts.emplace_back(std::sin(a) + 2 * std::sin(2 * a), std::cos(a) - 2 * std::cos(2 * a), -std::sin(3 * a), 0.3f);
    }
    const CurveFrames f(CurveView::chain(pts.data(), static_cast<uint32_t>(pts.size()), true));
    const YarnDescription d = touching_plies(3);
    const YarnTwist tw = yarn_twist(f, d);
    float largest_frame_share = 0;
    for (uint32_t seg = 0; seg < 12; ++seg)
        for (float t : {0.2f, 0.5f, 0.8f})
            for (int ply = 0; ply < 3; ++ply) {
                const float h = 2e-3f;
                const PlyCentre p = ply_centre(f.evaluate(seg, t), d, tw, ply);
                const Vec3 d1 = ply_centre(f.evaluate(seg, t + h), d, tw, ply).position -
                                ply_centre(f.evaluate(seg, t - h), d, tw, ply).position;
                const Vec3 a = normalize(d1), b = normalize(p.derivative);
                // atan2, not acos: a float cosine cannot tell angles this small apart.
                const float degrees = std::atan2(length(cross(a, b)), dot(a, b)) * 180 / kPi;
                EXPECT_LT(degrees, 0.02f) << "segment " << seg << ", t " << t << ", ply " << ply;
                const CurvePoint c = f.evaluate(seg, t);
                largest_frame_share = std::max(largest_frame_share, d.ply_distance * c.radius *
                                                                        std::fabs(c.frame_turn) / length(p.derivative));
            }
    EXPECT_GT(largest_frame_share, 0.005f);  // without the frame's turn the tangent would be > 0.3 deg off
}

// The local model decides alone only where it is clear by its margin (model_margin); with a
// margin of a whole yarn radius every crossing is settled and every entry refined on the exact
// curve. Both must give the same ply, point and N_i, on straight yarns and on a tight loop, for
// few and many plies, side and oblique views; the default spends fewer exact evaluations.
TEST(ImplicitPlies, ModelMarginNeverChangesTheResult) {
    for (float bend : {0.0f, 2.0f}) {
        const std::vector<Vec4> points = validation_curve(bend);
        const CurveFrames frames(CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), bend > 0));
        const ExplicitPlies tube(frames, touching_plies(3));
        for (int plies : {2, 5, 12}) {
            const YarnDescription d = touching_plies(plies);
            int model_evaluations = 0, exact_evaluations = 0;
            for (float view : {0.0f, 30.0f, 60.0f, 80.0f}) {
                const float psi = view * kPi / 180;
                for (int i = 0; i < 60; ++i) {
                    // Rays at the yarn from around it, offset across the tube, tilted by psi.
                    const uint32_t segment = 2 + static_cast<uint32_t>(i * 7) % (frames.segment_count() - 4);
                    const CurvePoint c = frames.evaluate(segment, 0.37f);
                    const float side = 0.7f * i, offset = std::fmod(0.37f * i, 1.9f) - 0.95f;
                    const Vec3 toward = c.normal * std::cos(side) + c.binormal * std::sin(side);
                    const Vec3 across = cross(c.tangent, toward);
                    const Vec3 dir = normalize(-toward * std::cos(psi) + c.tangent * std::sin(psi));
                    const Vec3 origin = c.position + across * (offset * c.radius) - dir * 10.0f;
                    const ExplicitHit entry = tube.intersect_tube(origin, dir, 0, 20);
                    if (!entry.hit) continue;
                    const YarnTubeHit h{origin, dir, entry.point, entry.segment, entry.t};
                    PlyTraceOptions exact;
                    exact.model_margin = 1;
                    PlySearchStats spent_a, spent_b;
                    const PlyHit a = trace(frames, d, h, {}, &spent_a), b = trace(frames, d, h, exact, &spent_b);
                    model_evaluations += spent_a.evaluations;
                    exact_evaluations += spent_b.evaluations;
                    ASSERT_EQ(a.hit, b.hit) << bend << " " << plies << " " << view << " " << i;
                    EXPECT_EQ(a.ply, b.ply);
                    EXPECT_EQ(a.plies_crossed, b.plies_crossed);
                    EXPECT_LT(length(a.point - b.point), 1e-4f);
                    EXPECT_EQ(spent_a.converged, spent_b.converged);
                }
            }
            EXPECT_LT(model_evaluations, exact_evaluations) << bend << " " << plies;
        }
    }
}

TEST(ImplicitPlies, LocalMethodAroundANeighbouringCrossSectionMatchesTheExactOne) {
    // Multi-scale's virtual rays enter the tube up to a few radii along the yarn from the
    // cross-section they are modelled around; on a straight yarn that must not matter.
    const StraightYarn y;
    const YarnDescription d = touching_plies(3);
    const YarnTwist tw = yarn_twist(y.frames, d);
    PlyTraceOptions local_method;
    local_method.cross_section = PlyCrossSection::local;
    int hits = 0;
    for (float psi : {0.0f, 0.6f, 1.1f})
        for (float h : {-0.8f, -0.3f, 0.1f, 0.55f, 0.9f})
            for (float shift : {-2.0f, 0.0f, 1.5f}) {
                const YarnTubeHit hit = side_hit(y.frames, h, psi, 20.0f);
                const CentrelineProjection around =
                    project_to_centreline(y.frames, hit.point + Vec3(0, 0, shift), hit.segment, hit.t);
                const PlyHit exact = trace_plies({y.frames, d, tw, hit});
                const PlyHit local = trace_plies({y.frames, d, tw, hit, &around}, local_method);
                ASSERT_EQ(local.hit, exact.hit) << psi << " " << h << " " << shift;
                if (!exact.hit) continue;
                ++hits;
                EXPECT_EQ(local.ply, exact.ply);
                EXPECT_EQ(local.plies_crossed, exact.plies_crossed);
                EXPECT_NEAR(local.distance, exact.distance, 1e-3f);
                EXPECT_GT(dot(local.tangent, exact.tangent), 0.99999f);
                EXPECT_GT(dot(local.normal, exact.normal), 0.9999f);
                EXPECT_NEAR(local.v_yarn, exact.v_yarn, 1e-3f);
            }
    EXPECT_GT(hits, 30);
}

}  // namespace
}  // namespace purl
