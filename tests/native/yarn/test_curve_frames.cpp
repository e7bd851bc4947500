#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "yarn/curve_frames.h"

namespace purl {
namespace {

constexpr float kTwoPi = 2 * kPi;

// Control points of a closed loop through f(angle), wrapped as YarnCurves stores loops.
template <class F>
std::vector<Vec4> loop(int n, F f, float radius = 0.1f) {
    std::vector<Vec4> p;
    for (int i = 0; i < n + 3; ++i) p.emplace_back(f(kTwoPi * (i % n) / n), radius);
    return p;
}

void expect_orthonormal(const CurvePoint& c) {
    EXPECT_NEAR(length(c.tangent), 1, 1e-5f);
    EXPECT_NEAR(length(c.normal), 1, 1e-5f);
    EXPECT_NEAR(length(c.binormal), 1, 1e-5f);
    EXPECT_NEAR(dot(c.tangent, c.normal), 0, 1e-5f);
    EXPECT_NEAR(dot(c.tangent, c.binormal), 0, 1e-5f);
    EXPECT_NEAR(dot(cross(c.tangent, c.normal), c.binormal), 1, 1e-5f);
}

// Rotation of the normal about the tangent per metre, by finite differences: zero for a
// rotation-minimizing frame.
float twist_rate(const CurveFrames& f, uint32_t segment, float t) {
    const float h = 1e-2f;
    const CurvePoint a = f.evaluate(segment, t - h), b = f.evaluate(segment, t + h);
    return dot(b.normal - a.normal, 0.5f * (a.binormal + b.binormal)) / (b.arc_length - a.arc_length);
}

TEST(CurveFrames, StraightYarnKeepsItsFrameAndMeasuresLength) {
    std::vector<Vec4> p;
    for (int i = 0; i < 10; ++i) p.emplace_back(0.0f, 0.0f, 0.5f * i, 0.1f);
    const CurveFrames f(CurveView::chain(p.data(), 10, false));
    ASSERT_EQ(f.segment_count(), 7u);
    const CurvePoint a = f.evaluate(0, 0), b = f.evaluate(6, 0.7f);
    EXPECT_NEAR(dot(a.normal, b.normal), 1, 1e-6f);
    EXPECT_NEAR(b.arc_length - a.arc_length, b.position.z - a.position.z, 1e-5f);
    EXPECT_NEAR(f.total_length(), 3.5f, 1e-5f);
    EXPECT_NEAR(a.radius, 0.1f, 1e-6f);
    EXPECT_NEAR(f.reference_radius(), 0.1f, 1e-6f);
    // Five floats per segment (normal, arc length, twist), plus the object.
    EXPECT_LE(f.memory_bytes(), sizeof(CurveFrames) + 8 * 5 * sizeof(float));
}

TEST(CurveFrames, HelixFrameDoesNotTwistWhereFrenetDoes) {
    // A helix of radius 1 and pitch 2 pi * 0.5: its Frenet frame turns about the tangent at
    // torsion 0.4 rad/m; a rotation-minimizing frame must not.
    std::vector<Vec4> p;
    for (int i = 0; i < 60; ++i) {
        const float a = 0.3f * i;
        p.emplace_back(std::cos(a), std::sin(a), 0.5f * a, 0.1f);
    }
    const CurveFrames f(CurveView::chain(p.data(), 60, false));
    float worst = 0;
    for (uint32_t s = 2; s < f.segment_count() - 2; ++s)
        for (float t : {0.1f, 0.5f, 0.9f}) {
            expect_orthonormal(f.evaluate(s, t));
            worst = std::max(worst, std::fabs(twist_rate(f, s, t)));
        }
    EXPECT_LT(worst, 0.01f);  // rad/m, against Frenet's 0.4
}

TEST(CurveFrames, PlanarLoopHasNoHolonomyAndExactLength) {
    const float radius = 3;
    const auto p = loop(48, [&](float a) { return Vec3(radius * std::cos(a), radius * std::sin(a), 0); });
    const CurveFrames f(CurveView::chain(p.data(), static_cast<uint32_t>(p.size()), true));
    ASSERT_EQ(f.segment_count(), 48u);
    // The B-spline of points on a circle runs at radius (2 + cos(step)) / 3 of theirs.
    const float step = kTwoPi / 48, spline_radius = radius * (2 + std::cos(step)) / 3;
    EXPECT_NEAR(f.total_length(), kTwoPi * spline_radius, 1e-3f * spline_radius);
    // For a planar curve the rotation-minimizing frame keeps one axis on the plane's normal.
    for (uint32_t s = 0; s < 48; s += 5) {
        const CurvePoint c = f.evaluate(s, 0.3f);
        expect_orthonormal(c);
        EXPECT_NEAR(std::fabs(c.binormal.z) + std::fabs(c.normal.z), 1, 1e-4f);
    }
}

TEST(CurveFrames, NonPlanarLoopIsContinuousAcrossTheSeam) {
    // A trefoil knot: its frame picks up about 2.2 rad of holonomy, which must be spread out.
    const auto p = loop(60, [](float a) {
        return Vec3(std::sin(a) + 2 * std::sin(2 * a), std::cos(a) - 2 * std::cos(2 * a), -std::sin(3 * a));
    });
    const CurveFrames f(CurveView::chain(p.data(), static_cast<uint32_t>(p.size()), true));
    const CurvePoint end = f.evaluate(59, 1.0f), start = f.evaluate(0, 0.0f);
    EXPECT_NEAR(length(end.position - start.position), 0, 1e-5f);
    EXPECT_NEAR(dot(end.normal, start.normal), 1, 1e-6f);
    EXPECT_NEAR(end.arc_length, f.total_length(), 1e-5f);
    EXPECT_NEAR(start.arc_length, 0, 1e-6f);
    // Continuous at every interior boundary too, and the spread twist is uniform and small.
    float first_rate = twist_rate(f, 3, 0.5f);
    for (uint32_t s = 1; s < 60; ++s) {
        EXPECT_NEAR(dot(f.evaluate(s - 1, 1).normal, f.evaluate(s, 0).normal), 1, 1e-6f);
        EXPECT_NEAR(twist_rate(f, s, 0.5f), first_rate, 0.01f);
    }
    EXPECT_GT(std::fabs(first_rate), 0.05f);  // the loop does have holonomy to spread
}

TEST(CurveFrames, FrameTurnAndArcRateMatchFiniteDifferences) {
    // A coarse trefoil: few control points, so the interpolated frame turns visibly about the
    // tangent and the Hermite arc length departs from the true one.
    const auto p = loop(12, [](float a) {
        return Vec3(std::sin(a) + 2 * std::sin(2 * a), std::cos(a) - 2 * std::cos(2 * a), -std::sin(3 * a));
    });
    const CurveFrames f(CurveView::chain(p.data(), static_cast<uint32_t>(p.size()), true));
    float largest_turn = 0, largest_arc_change = 0;
    for (uint32_t s = 0; s < 12; ++s)
        for (float t : {0.1f, 0.35f, 0.6f, 0.9f}) {
            const float h = 2e-3f;
            const CurvePoint c = f.evaluate(s, t), a = f.evaluate(s, t - h), b = f.evaluate(s, t + h);
            const float ds = 2 * h * c.speed;
            const float turn = dot(b.normal - a.normal, c.binormal) / ds;
            EXPECT_NEAR(c.frame_turn, turn, 2e-3f + 2e-3f * std::fabs(c.frame_turn))
                << "segment " << s << ", t " << t;
            EXPECT_NEAR(c.arc_rate, (b.arc_length - a.arc_length) / ds, 1e-3f) << "segment " << s << ", t " << t;
            largest_turn = std::max(largest_turn, std::fabs(c.frame_turn));
            largest_arc_change = std::max(largest_arc_change, std::fabs(c.arc_rate - 1));
        }
    EXPECT_GT(largest_turn, 0.05f);  // the test means something: the frame does turn
    EXPECT_GT(largest_arc_change, 1e-3f);
    // Only the centre-line: the frame quantities keep their neutral values.
    const CurvePoint centreline = f.evaluate_centreline(3, 0.5f);
    EXPECT_EQ(centreline.frame_turn, 0.0f);
    EXPECT_EQ(centreline.arc_rate, 1.0f);
}

TEST(CurveFrames, FramesFollowARigidMotion) {
    const auto p = loop(24, [](float a) { return Vec3(std::cos(a), 1.5f * std::sin(a), 0.3f * std::cos(3 * a)); });
    // Rotate by 40 degrees about (1, 2, 3) and move.
    const Vec3 axis = normalize(Vec3(1, 2, 3));
    const float angle = 0.7f, c = std::cos(angle), s = std::sin(angle);
    auto move = [&](Vec3 v) {
        return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1 - c)) + Vec3(5, -2, 7);
    };
    std::vector<Vec4> q;
    for (const Vec4& v : p) q.emplace_back(move(v.xyz()), v.w);
    const CurveFrames a(CurveView::chain(p.data(), static_cast<uint32_t>(p.size()), true));
    const CurveFrames b(CurveView::chain(q.data(), static_cast<uint32_t>(q.size()), true));
    const Vec3 offset_dir = normalize(Vec3(0.2f, -0.5f, 0.8f));
    for (uint32_t seg : {0u, 7u, 19u}) {
        const CurvePoint ca = a.evaluate(seg, 0.4f), cb = b.evaluate(seg, 0.4f);
        const Vec3 pa = ca.position + offset_dir * 0.05f;
        const Vec3 pb = move(pa);
        EXPECT_NEAR(CurveFrames::azimuth(ca, pa), CurveFrames::azimuth(cb, pb), 1e-4f);
        EXPECT_NEAR(ca.arc_length, cb.arc_length, 1e-4f);
        EXPECT_NEAR(length(move(ca.normal) - move(Vec3(0.0f)) - cb.normal), 0, 1e-4f);
    }
}

TEST(CurveFrames, SeparateSegmentsMatchTheChain) {
    std::vector<Vec4> p;
    for (int i = 0; i < 12; ++i) p.emplace_back(std::cos(0.5f * i), std::sin(0.7f * i), 0.3f * i, 0.1f);
    // The same curve as segments with their own four points each.
    std::vector<Vec4> q;
    std::vector<uint32_t> first;
    for (uint32_t s = 0; s + 3 < p.size(); ++s) {
        first.push_back(static_cast<uint32_t>(q.size()));
        for (int k = 0; k < 4; ++k) q.push_back(p[s + k]);
    }
    const CurveFrames chain(CurveView::chain(p.data(), 12, false));
    const CurveFrames split(CurveView::separate_segments(q.data(), static_cast<uint32_t>(q.size()), first.data(),
                                                         static_cast<uint32_t>(first.size()), false));
    ASSERT_EQ(chain.segment_count(), split.segment_count());
    for (uint32_t s = 0; s < chain.segment_count(); ++s) {
        const CurvePoint a = chain.evaluate(s, 0.25f), b = split.evaluate(s, 0.25f);
        EXPECT_NEAR(length(a.normal - b.normal), 0, 1e-5f);
        EXPECT_NEAR(a.arc_length, b.arc_length, 1e-5f);
    }
}

TEST(CurveFrames, AdvanceWrapsLoopsAndStopsAtOpenEnds) {
    std::vector<Vec4> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(float(i), 0.0f, 0.0f, 0.1f);
    const CurveFrames open(CurveView::chain(p.data(), 8, false));
    uint32_t seg = 1;
    float t = 0.5f;
    EXPECT_TRUE(open.advance(seg, t, 2.25f));
    EXPECT_EQ(seg, 3u);
    EXPECT_NEAR(t, 0.75f, 1e-6f);
    EXPECT_FALSE(open.advance(seg, t, 10.0f));
    EXPECT_EQ(seg, 4u);
    EXPECT_LE(t, 1.5f);
    const auto l = loop(6, [](float a) { return Vec3(std::cos(a), std::sin(a), 0); });
    const CurveFrames closed(CurveView::chain(l.data(), 9, true));
    seg = 5;
    t = 0.5f;
    EXPECT_TRUE(closed.advance(seg, t, 1.0f));
    EXPECT_EQ(seg, 0u);
    EXPECT_TRUE(closed.advance(seg, t, -1.0f));
    EXPECT_EQ(seg, 5u);
}

TEST(CurveFrames, BuildsEveryCurveOfAnArraySet) {
    std::vector<Vec4> p;
    for (int i = 0; i < 6; ++i) p.emplace_back(float(i), 0.0f, 0.0f, 0.1f);
    for (int i = 0; i < 5 + 3; ++i) p.emplace_back(std::cos(i * 1.2566f), std::sin(i * 1.2566f), 1.0f, 0.2f);
    const uint32_t offsets[] = {0, 6, 14};
    const uint8_t closed[] = {0, 1};
    const auto frames = build_curve_frames(p.data(), offsets, closed, 2);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].segment_count(), 3u);
    EXPECT_FALSE(frames[0].closed());
    EXPECT_EQ(frames[1].segment_count(), 5u);
    EXPECT_TRUE(frames[1].closed());
    EXPECT_NEAR(frames[1].reference_radius(), 0.2f, 1e-6f);
}

}  // namespace
}  // namespace purl
