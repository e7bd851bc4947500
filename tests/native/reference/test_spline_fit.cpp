// Interpolating B-splines and the arc-length index the explicit curves are built from.
#include <gtest/gtest.h>

#include <cmath>

#include "math/bspline.h"
#include "yarn/arc_length.h"
#include "reference/explicit_sampling.h"
#include "reference/spline_fit.h"
#include "reference_fixture.h"

namespace purl::test {
namespace {

Vec4 eval_chain(const std::vector<Vec4>& cp, size_t segment, float t) {
    const BSplineWeights w = bspline_basis(t);
    Vec4 r(0, 0, 0, 0);
    for (int i = 0; i < 4; ++i) {
        const Vec4& p = cp[segment + i];
        r = Vec4(r.x + p.x * w.w[i], r.y + p.y * w.w[i], r.z + p.z * w.w[i], r.w + p.w * w.w[i]);
    }
    return r;
}

std::vector<Vec4> wrap(std::vector<Vec4> cp) {
    for (int i = 0; i < 3; ++i) cp.push_back(cp[i]);
    return cp;
}

TEST(SplineFit, ClosedCurvePassesThroughEverySampleAndStaysNearTheCircle) {
    // A circle of radius r sampled n times: exact at the knots, within 5/384 h^4 r w^4 between.
    const double r = 2.0;
    for (int n : {4, 7, 16, 64}) {
        std::vector<Point4d> s(n);
        for (int j = 0; j < n; ++j) s[j] = {{r * std::cos(2 * M_PI * j / n), r * std::sin(2 * M_PI * j / n), 0.5, 0.1}};
        const std::vector<Vec4> cp = wrap(interpolate_closed(s));
        ASSERT_EQ(cp.size(), size_t(n + 3));
        const double bound = 5.0 / 384 * std::pow(2 * M_PI / n, 4) * r;
        for (int j = 0; j < n; ++j) {
            const Vec4 k = eval_chain(cp, j, 0.0f);
            EXPECT_NEAR(k.x, s[j].v[0], 2e-6);
            EXPECT_NEAR(k.y, s[j].v[1], 2e-6);
            EXPECT_NEAR(k.w, 0.1, 1e-7);
            const Vec4 mid = eval_chain(cp, j, 0.5f);
            EXPECT_LE(std::fabs(std::hypot(mid.x, mid.y) - r), 1.05 * bound + 1e-6) << n;
        }
    }
}

TEST(SplineFit, OpenCurveReproducesCubicsExactly) {
    // With the cubic's own end slopes the spline through samples of a cubic is that cubic.
    auto f = [](double x) { return 0.3 * x * x * x - 1.1 * x * x + 0.2 * x + 4; };
    const int n = 9;
    std::vector<Point4d> s(n);
    for (int j = 0; j < n; ++j) s[j] = {{double(j), f(j), -f(j), 0.05 + 0.01 * j}};
    const std::vector<Vec4> cp = interpolate_open(s);
    ASSERT_EQ(cp.size(), size_t(n + 2));
    for (int j = 0; j + 1 < n; ++j)
        for (float t : {0.0f, 0.25f, 0.5f, 0.9f, 1.0f}) {
            const Vec4 v = eval_chain(cp, j, t);
            EXPECT_NEAR(v.x, j + t, 1e-5);
            EXPECT_NEAR(v.y, f(j + t), 1e-4) << j << " " << t;
            EXPECT_NEAR(v.w, 0.05 + 0.01 * (j + t), 1e-6);
        }
}

TEST(ArcLength, FindsThePointAtEveryArcLength) {
    std::vector<YarnCurves> yarns = {wavy_yarn(0.1f), loop_yarn(0.1f, 5)};
    if (have_shared_data("glove.bcc")) yarns.push_back(glove_yarns(2));
    for (const YarnCurves& curves : yarns) {
        const std::vector<CurveFrames> frames = yarn_set_frames(curves);
        for (const CurveFrames& f : frames) {
            const ArcLengthIndex index(f);
            EXPECT_NEAR(index.length(), f.total_length(), 1e-6f * f.total_length());
            for (int k = 0; k <= 500; ++k) {
                const float s = index.length() * k / 500;
                CurveParam p;
                const CurvePoint c = index.point_at(s, &p);
                EXPECT_NEAR(c.arc_length, s, 2e-6f * index.length()) << k;
                const CurvePoint again = f.evaluate(p.segment, p.t);
                EXPECT_EQ(again.position.x, c.position.x);
            }
        }
    }
    GTEST_SKIP_WITHOUT_SHARED_DATA("glove.bcc");  // after the synthetic yarns, which ran
}

}  // namespace
}  // namespace purl::test
