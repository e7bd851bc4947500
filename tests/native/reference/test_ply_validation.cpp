// Implicit plies against explicit helix tubes: the accuracy targets of issue 3. Fails when
// accuracy regresses; prints the measured table (also in docs/implicit-geometry.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "reference/explicit_plies.h"
#include "reference/ply_validation.h"

namespace purl {
namespace {

constexpr int kPlyCounts[] = {2, 3, 5, 12};

double mean_of(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return v.empty() ? 0 : s / v.size();
}

struct Totals {
    long rays = 0, unconverged = 0, non_finite = 0, unresolved = 0;
    void add(const ValidationResult& r) {
        rays += r.elliptical.rays;
        unconverged += r.elliptical.unconverged;
        non_finite += r.elliptical.non_finite + r.circular.non_finite;
        unresolved += r.reference_unresolved;
    }
};

ValidationResult run(int plies, float angle, float curvature, int rays, Totals& totals, int count_crossings = 0,
                     PlyCrossSection method = PlyCrossSection::elliptical) {
    ValidationCase c;
    c.count_crossings_every = count_crossings;
    c.description = touching_plies(plies);
    c.view_angle = angle;
    c.curvature_radius = curvature;
    c.rays = rays;
    c.seed = 1000 * plies + static_cast<uint64_t>(angle) + 7 * static_cast<uint64_t>(curvature);
    PlyTraceOptions options;
    options.cross_section = method;
    const ValidationResult r = validate_plies(c, options);
    totals.add(r);
    const MethodStats &e = r.elliptical, &ci = r.circular;
    std::printf("%s bend %4.0f  plies %2d  view %2.0f | agree ell %.4f circ %.4f | tangent err ell %.3f circ %.3f deg"
                " | normal err ell %.3f circ %.3f | same ply %d/%d | evals/ply mean %.1f | N_i ok %d/%d\n",
                method == PlyCrossSection::local ? "local" : "exact", curvature, plies, angle, e.agreement(),
                ci.agreement(), mean_of(e.tangent_error),
                mean_of(ci.tangent_error), mean_of(e.normal_error), mean_of(ci.normal_error), e.same_ply, e.both_hit,
                e.mean(std::vector<float>(e.iterations.begin(), e.iterations.end())), e.crossed_agree,
                e.crossed_checked);
    return r;
}

TEST(PlyValidation, ReferenceMatchesAnalyticCylinders) {
    // Without twist the plies are straight cylinders: the explicit trace must be exact.
    const std::vector<Vec4> pts = validation_curve(0.0f);
    const CurveFrames f(CurveView::chain(pts.data(), static_cast<uint32_t>(pts.size()), false));
    YarnDescription d = touching_plies(3, 0.0f);
    const ExplicitPlies ex(f, d);
    const YarnTwist tw = yarn_twist(f, d);
    for (int i = 0; i < 30; ++i) {
        const Vec3 dir = normalize(Vec3(-1, 0.1f * (i % 7) - 0.3f, 0.05f * i - 0.7f));
        const Vec3 origin(5, 0.07f * i - 1, 40);
        float best = 1e30f;
        for (int p = 0; p < 3; ++p) {
            // Ray against the infinite cylinder of ply p (axis along z).
            const PlyCentre c = ply_centre(f.evaluate(30, 0), d, tw, p);
            const Vec3 w = origin - c.position;
            const float a = dir.x * dir.x + dir.y * dir.y, b = w.x * dir.x + w.y * dir.y;
            const float cc = w.x * w.x + w.y * w.y - c.radius * c.radius, disc = b * b - a * cc;
            if (disc >= 0) best = std::min(best, (-b - std::sqrt(disc)) / a);
        }
        const ExplicitHit h = ex.intersect_plies(origin, dir, 0, 20);
        ASSERT_TRUE(h.resolved);
        ASSERT_EQ(h.hit, best < 1e29f) << i;
        if (h.hit) {
            EXPECT_NEAR(h.distance, best, 1e-4f) << i;
        }
    }
}

TEST(PlyValidation, StraightYarnsMeetTheIssueTargets) {
    Totals totals;
    for (int plies : kPlyCounts) {
        for (float angle : {0.0f, 30.0f, 45.0f, 60.0f, 70.0f}) {
            const ValidationResult r = run(plies, angle, 0, 400, totals, 8);
            // Target: at least 99% hit/miss agreement up to 70 degrees.
            EXPECT_GE(r.elliptical.agreement(), 0.99) << plies << " plies at " << angle;
            // Same ply and a tangent within a degree on at least 99% of the common hits.
            EXPECT_GE(r.elliptical.same_ply, 0.99 * r.elliptical.both_hit);
            EXPECT_LT(r.elliptical.percentile(r.elliptical.tangent_error, 0.99), 1.0) << plies << " " << angle;
            if (angle == 60.0f) {
                // Target: elliptical mean tangent error at most a third of the circular one.
                EXPECT_LE(mean_of(r.elliptical.tangent_error), mean_of(r.circular.tangent_error) / 3)
                    << plies << " plies";
            }
        }
    }
    EXPECT_EQ(totals.non_finite, 0);
    EXPECT_LT(totals.unconverged, 0.001 * totals.rays);
    EXPECT_EQ(totals.unresolved, 0);
}

TEST(PlyValidation, GrazingViewsAndTightBendsStayAccurate) {
    // Beyond the issue's targets: guards at the measured level (see the doc) minus a margin.
    Totals totals;
    for (int plies : kPlyCounts) {
        for (float angle : {80.0f, 85.0f}) {
            const ValidationResult r = run(plies, angle, 0, 200, totals);
            EXPECT_GE(r.elliptical.agreement(), 0.98) << plies << " plies at " << angle;
        }
        for (float bend : {8.0f, 4.0f, 2.0f})
            for (float angle : {0.0f, 45.0f, 70.0f, 85.0f}) {
                const ValidationResult r = run(plies, angle, bend, 100, totals);
                EXPECT_GE(r.elliptical.agreement(), 0.97) << plies << " plies, bend " << bend << " at " << angle;
                EXPECT_GE(r.elliptical.same_ply, 0.95 * r.elliptical.both_hit);
                EXPECT_LE(mean_of(r.elliptical.tangent_error), std::max(0.5, mean_of(r.circular.tangent_error) / 3));
            }
    }
    std::printf("rays %ld, unconverged %ld, non-finite %ld, reference unresolved %ld\n", totals.rays,
                totals.unconverged, totals.non_finite, totals.unresolved);
    EXPECT_EQ(totals.non_finite, 0);
    EXPECT_LT(totals.unconverged, 0.001 * totals.rays);
}

TEST(PlyValidation, LocalMethodIsExactOnStraightYarnsAndCloseOnBends) {
    // The yarn straightened at the hit (what multi-scale's virtual rays use): the issue's
    // targets on straight yarns at every angle; on bends it drifts with the stretch an oblique
    // ray crosses (measured: agreement >= 0.935, mean tangent error <= 1.2 deg at bend 2 R).
    Totals totals;
    for (int plies : kPlyCounts) {
        for (float angle : {0.0f, 45.0f, 60.0f, 70.0f, 85.0f}) {
            const ValidationResult r = run(plies, angle, 0, 200, totals, 8, PlyCrossSection::local);
            EXPECT_GE(r.elliptical.agreement(), 0.99) << plies << " plies at " << angle;
            EXPECT_GE(r.elliptical.same_ply, 0.99 * r.elliptical.both_hit) << plies << " plies at " << angle;
            EXPECT_LT(r.elliptical.percentile(r.elliptical.tangent_error, 0.99), 0.1) << plies << " " << angle;
        }
        for (float bend : {4.0f, 2.0f})
            for (float angle : {0.0f, 60.0f, 85.0f}) {
                const ValidationResult r = run(plies, angle, bend, 100, totals, 0, PlyCrossSection::local);
                EXPECT_GE(r.elliptical.agreement(), angle == 0 ? 0.99 : 0.90)
                    << plies << ", bend " << bend << " at " << angle;
                EXPECT_LE(mean_of(r.elliptical.tangent_error), std::max(0.1, mean_of(r.circular.tangent_error) / 3))
                    << plies << " plies, bend " << bend << " at " << angle;
            }
    }
    EXPECT_EQ(totals.non_finite, 0);
}

}  // namespace
}  // namespace purl
