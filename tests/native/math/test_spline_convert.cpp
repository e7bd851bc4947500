// Exactness of the basis changes to B-splines, and why Catmull-Rom needs per-segment points.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "math/rng.h"
#include "math/spline_convert.h"

namespace purl {
namespace {

std::vector<Vec4> random_points(size_t n, uint64_t seed, float scale = 30.0f) {
    Rng rng(seed);
    std::vector<Vec4> p(n);
    for (Vec4& v : p)
        v = Vec4(scale * (rng.next_float() - 0.5f), scale * (rng.next_float() - 0.5f),
                 scale * (rng.next_float() - 0.5f), 0.1f + rng.next_float());
    return p;
}

float dist4(Vec4 a, Vec4 b) {
    return std::sqrt(sqr(a.x - b.x) + sqr(a.y - b.y) + sqr(a.z - b.z) + sqr(a.w - b.w));
}

// Largest distance between a reference curve (given per segment) and the converted segments.
template <class RefEval>
float max_error(const BSplineSegments& seg, size_t segments, RefEval ref, int samples = 200) {
    EXPECT_EQ(seg.segment_count(), segments);
    float worst = 0;
    for (size_t s = 0; s < seg.segment_count(); ++s)
        for (int k = 0; k <= samples; ++k) {
            const float t = float(k) / samples;
            worst = std::max(worst, dist4(seg.evaluate(s, t), ref(s, t)));
        }
    return worst;
}

TEST(SplineConvert, CatmullRomOpenIsExact) {
    const size_t n = 40;
    const std::vector<Vec4> p = random_points(n, 1);
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, p.data(), n, false);
    // BCC convention: open curves run from p[1] to p[n-2].
    const float err = max_error(seg, n - 3, [&](size_t s, float t) { return eval_catmull_rom(&p[s], t); });
    EXPECT_LT(err, 1e-5f * 30.0f);
    EXPECT_NEAR(seg.evaluate(0, 0).x, p[1].x, 1e-4f);
    EXPECT_NEAR(seg.evaluate(n - 4, 1).y, p[n - 2].y, 1e-4f);
}

TEST(SplineConvert, CatmullRomClosedIsExactAndCoversTheLoop) {
    const size_t n = 25;
    const std::vector<Vec4> p = random_points(n, 2);
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, p.data(), n, true);
    const float err = max_error(seg, n, [&](size_t s, float t) {
        const Vec4 cr[4] = {p[(s + n - 1) % n], p[s], p[(s + 1) % n], p[(s + 2) % n]};
        return eval_catmull_rom(cr, t);
    });
    EXPECT_LT(err, 1e-5f * 30.0f);
    // Segment s passes through p[s] and the last segment returns to p[0].
    for (size_t s = 0; s < n; ++s) EXPECT_LT(dist4(seg.evaluate(s, 0), p[s]), 1e-4f);
    EXPECT_LT(dist4(seg.evaluate(n - 1, 1), p[0]), 1e-4f);
}

// The evidence for per-segment control points: a B-spline chain is C2 at every join, an
// exact Catmull-Rom curve is not, so no chain can reproduce it.
Vec4 second_derivative(const Vec4 bs[4], float t) {
    const float w[4] = {1 - t, 3 * t - 2, -3 * t + 1, t};
    Vec4 r;
    for (int i = 0; i < 4; ++i) {
        r.x += w[i] * bs[i].x;
        r.y += w[i] * bs[i].y;
        r.z += w[i] * bs[i].z;
        r.w += w[i] * bs[i].w;
    }
    return r;
}

TEST(SplineConvert, CatmullRomIsNotC2SoNoSingleChainIsExact) {
    const size_t n = 30;
    const std::vector<Vec4> p = random_points(n, 3);
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, p.data(), n, false);
    EXPECT_FALSE(seg.is_chain());
    float smallest_jump = 1e30f;
    for (size_t s = 0; s + 1 < seg.segment_count(); ++s) {
        const Vec4 a = second_derivative(&seg.points[seg.segment_first[s]], 1.0f);
        const Vec4 b = second_derivative(&seg.points[seg.segment_first[s + 1]], 0.0f);
        // Predicted jump: p0 - 2 p1 + 2 p3 - p4 for the points of segments s, s+1.
        const Vec4* q = &p[s];
        const float px = q[0].x - 2 * q[1].x + 2 * q[3].x - q[4].x;
        EXPECT_NEAR(b.x - a.x, px, 1e-3f);
        smallest_jump = std::min(smallest_jump, dist4(a, b));
        // Sharing three points (a chain) would force the jump to zero.
        const Vec4* sa = &seg.points[seg.segment_first[s]];
        const Vec4* sb = &seg.points[seg.segment_first[s + 1]];
        EXPECT_GT(dist4(sa[1], sb[0]) + dist4(sa[2], sb[1]) + dist4(sa[3], sb[2]), 1e-3f);
    }
    EXPECT_GT(smallest_jump, 1.0f);  // random data on a 30-unit box: jumps are O(10)

    // A genuine chain is C2: the same measure is zero up to rounding.
    const std::vector<Vec4> chain = random_points(n, 4);
    for (size_t s = 0; s + 4 < n; ++s)
        EXPECT_LT(dist4(second_derivative(&chain[s], 1.0f), second_derivative(&chain[s + 1], 0.0f)), 1e-3f);
}

TEST(SplineConvert, CatmullRomOfAQuadraticSharesPointsLikeAChain) {
    // Uniform samples of one quadratic: CR reproduces quadratics (its tangents are central
    // differences), the curve is C-infinity, and consecutive converted segments overlap in
    // 3 points as a chain would. (Cubic data already breaks this: CR is not exact for cubics.)
    std::vector<Vec4> p(10);
    for (int i = 0; i < 10; ++i) {
        const float u = float(i);
        p[i] = Vec4(u, 0.1f * u * u - 0.3f * u, 2 - u, 1 + 0.05f * u);
    }
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, p.data(), p.size(), false);
    for (size_t s = 0; s + 1 < seg.segment_count(); ++s)
        for (int k = 0; k < 3; ++k)
            EXPECT_LT(dist4(seg.points[seg.segment_first[s] + k + 1], seg.points[seg.segment_first[s + 1] + k]), 1e-4f);
}

TEST(SplineConvert, BezierOpenAndClosedAreExact) {
    const size_t k = 9;
    const std::vector<Vec4> open = random_points(3 * k + 1, 5);
    const BSplineSegments a = to_bspline_segments(CurveBasis::Bezier, open.data(), open.size(), false);
    EXPECT_LT(max_error(a, k, [&](size_t s, float t) { return eval_bezier(&open[3 * s], t); }), 3e-4f);
    EXPECT_FALSE(a.is_chain());

    const std::vector<Vec4> loop = random_points(3 * k, 6);
    const BSplineSegments b = to_bspline_segments(CurveBasis::Bezier, loop.data(), loop.size(), true);
    EXPECT_LT(max_error(b, k, [&](size_t s, float t) {
                  const Vec4 bz[4] = {loop[3 * s], loop[3 * s + 1], loop[3 * s + 2], loop[(3 * s + 3) % loop.size()]};
                  return eval_bezier(bz, t);
              }),
              3e-4f);
    EXPECT_LT(dist4(b.evaluate(k - 1, 1.0f), loop[0]), 1e-4f);
}

TEST(SplineConvert, BezierRoundTripAndSegmentHelpersInvert) {
    const std::vector<Vec4> p = random_points(4, 7);
    Vec4 bs[4], back[4];
    bezier_to_bspline(p.data(), bs);
    bspline_to_bezier(bs, back);
    for (int i = 0; i < 4; ++i) EXPECT_LT(dist4(back[i], p[i]), 1e-4f);
    for (int k = 0; k <= 20; ++k)
        EXPECT_LT(dist4(eval_bspline(bs, k / 20.0f), eval_bezier(p.data(), k / 20.0f)), 1e-4f);
}

TEST(SplineConvert, RadiusFollowsTheSameLinearMap) {
    // Constant position, varying radius: the radius curve must be the CR curve of the radii.
    std::vector<Vec4> p = {{0, 0, 0, 1}, {0, 0, 0, 2}, {0, 0, 0, 5}, {0, 0, 0, 3}};
    const BSplineSegments seg = to_bspline_segments(CurveBasis::CatmullRom, p.data(), 4, false);
    for (int k = 0; k <= 10; ++k)
        EXPECT_NEAR(seg.evaluate(0, k / 10.0f).w, eval_catmull_rom(p.data(), k / 10.0f).w, 1e-5f);
    EXPECT_NEAR(seg.evaluate(0, 0).w, 2.0f, 1e-5f);
    EXPECT_NEAR(seg.evaluate(0, 1).w, 5.0f, 1e-5f);
}

TEST(SplineConvert, BSplineIsPassedThroughAsAChain) {
    const std::vector<Vec4> p = random_points(12, 8);
    const BSplineSegments open = to_bspline_segments(CurveBasis::BSpline, p.data(), 12, false);
    EXPECT_TRUE(open.is_chain());
    EXPECT_EQ(open.segment_count(), 9u);
    EXPECT_EQ(open.points.size(), 12u);
    const BSplineSegments loop = to_bspline_segments(CurveBasis::BSpline, p.data(), 12, true);
    EXPECT_TRUE(loop.is_chain());
    EXPECT_EQ(loop.segment_count(), 12u);
    ASSERT_EQ(loop.points.size(), 15u);
    EXPECT_EQ(loop.points[13].x, p[1].x);
    EXPECT_LT(dist4(loop.evaluate(11, 1.0f), loop.evaluate(0, 0.0f)), 1e-5f);  // closes
}

TEST(SplineConvert, PolylineInterpolationPassesThroughEveryPoint) {
    for (bool closed : {false, true}) {
        const std::vector<Vec4> p = random_points(50, 9);
        const BSplineSegments seg = to_bspline_segments(CurveBasis::Polyline, p.data(), p.size(), closed);
        EXPECT_TRUE(seg.is_chain());
        ASSERT_EQ(seg.segment_count(), closed ? 50u : 49u);
        for (size_t i = 0; i < seg.segment_count(); ++i) EXPECT_LT(dist4(seg.evaluate(i, 0), p[i]), 1e-4f);
        const Vec4 last = seg.evaluate(seg.segment_count() - 1, 1.0f);
        EXPECT_LT(dist4(last, closed ? p[0] : p.back()), 1e-4f);
    }
}

TEST(SplineConvert, PolylineOpenEndsAreNatural) {
    const std::vector<Vec4> p = random_points(7, 10);
    const std::vector<Vec4> c = interpolate_bspline(p.data(), p.size(), false);
    ASSERT_EQ(c.size(), 9u);
    EXPECT_LT(dist4(second_derivative(&c[0], 0.0f), Vec4()), 1e-3f);
    EXPECT_LT(dist4(second_derivative(&c[5], 1.0f), Vec4()), 1e-3f);
    // Two points: a straight segment between them.
    const std::vector<Vec4> line = interpolate_bspline(p.data(), 2, false);
    for (int k = 0; k <= 10; ++k) {
        const float t = k / 10.0f;
        const Vec4 e = eval_bspline(line.data(), t);
        EXPECT_NEAR(e.x, p[0].x + t * (p[1].x - p[0].x), 1e-4f);
    }
}

// Distance from q to the polyline segment a-b.
float distance_to_segment(Vec3 q, Vec3 a, Vec3 b) {
    const Vec3 ab = b - a;
    const float t = clamp(dot(q - a, ab) / std::max(1e-30f, dot(ab, ab)), 0.0f, 1.0f);
    return length(q - (a + ab * t));
}

TEST(SplineConvert, PolylineDeviationIsSmallForSmoothSamples) {
    // A closed loop sampled like BCC yarns (~0.24 spacing on radius 5): the interpolated
    // curve stays within a tiny fraction of the spacing of the polyline and of the circle.
    const int n = 130;
    const float radius = 5.0f;
    std::vector<Vec4> p(n);
    for (int i = 0; i < n; ++i) {
        const float a = 2 * kPi * i / n;
        p[i] = Vec4(radius * std::cos(a), radius * std::sin(a), 0.3f * std::sin(3 * a), 0.1f);
    }
    const BSplineSegments seg = to_bspline_segments(CurveBasis::Polyline, p.data(), n, true);
    float to_polyline = 0, to_circle = 0;
    for (int s = 0; s < n; ++s)
        for (int k = 0; k <= 20; ++k) {
            const Vec3 q = seg.evaluate(s, k / 20.0f).xyz();
            to_polyline = std::max(to_polyline, distance_to_segment(q, p[s].xyz(), p[(s + 1) % n].xyz()));
            to_circle = std::max(to_circle, std::fabs(std::hypot(q.x, q.y) - radius));
        }
    const float spacing = 2 * kPi * radius / n;
    RecordProperty("polyline_deviation_over_spacing", std::to_string(to_polyline / spacing));
    std::cout << "circle polyline: spline deviates " << to_polyline / spacing << " spacings from the polyline, "
              << to_circle / spacing << " from the circle\n";
    EXPECT_LT(to_polyline, 0.02f * spacing);  // sagitta of a chord is ~spacing^2 / (8 radius)
    EXPECT_LT(to_circle, 1e-3f * spacing);
}

TEST(SplineConvert, RejectsPointCountsABasisCannotUse) {
    const std::vector<Vec4> p = random_points(8, 11);
    EXPECT_THROW(to_bspline_segments(CurveBasis::BSpline, p.data(), 3, false), std::invalid_argument);
    EXPECT_THROW(to_bspline_segments(CurveBasis::CatmullRom, p.data(), 2, true), std::invalid_argument);
    EXPECT_THROW(to_bspline_segments(CurveBasis::Bezier, p.data(), 6, false), std::invalid_argument);
    EXPECT_THROW(to_bspline_segments(CurveBasis::Bezier, p.data(), 7, true), std::invalid_argument);
    EXPECT_THROW(to_bspline_segments(CurveBasis::Polyline, p.data(), 1, false), std::invalid_argument);
    EXPECT_NO_THROW(to_bspline_segments(CurveBasis::Bezier, p.data(), 7, false));
    EXPECT_NO_THROW(to_bspline_segments(CurveBasis::Bezier, p.data(), 6, true));
}

}  // namespace
}  // namespace purl
