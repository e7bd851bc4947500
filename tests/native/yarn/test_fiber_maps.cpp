#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "yarn/fiber_maps.h"
#include "yarn/ply_cross_section.h"

namespace purl {
namespace {

TEST(PlyCrossSection, ZhaoDensityEndsAndShape) {
    EXPECT_NEAR(fiber_density(0, 0.1f, 0.5f), 0.9f, 1e-6f);
    EXPECT_NEAR(fiber_density(1, 0.1f, 0.5f), 0.1f, 1e-6f);
    for (float r = 0.05f; r <= 1; r += 0.05f)
        EXPECT_LT(fiber_density(r, 0.1f, 0.5f), fiber_density(r - 0.05f, 0.1f, 0.5f));
}

TEST(PlyCrossSection, FiberCentresFollowTheDensity) {
    YarnDescription d = default_yarn_description();
    d.fiber_count = 2000;
    d.density_eps = 0.05f;
    d.density_beta = 1.0f;
    d.migration_rho_min = d.migration_rho_max = 1;  // rest positions
    const Circles2D c = ply_fibers(d, 0);
    ASSERT_EQ(c.centres.size(), 2000u);
    // Mean distance from the centre against the density's: int r p(r) r dr / int p(r) r dr.
    double num = 0, den = 0;
    for (int i = 0; i < 1000; ++i) {
        const double r = (i + 0.5) / 1000;
        num += r * r * fiber_density(float(r), 0.05f, 1.0f);
        den += r * fiber_density(float(r), 0.05f, 1.0f);
    }
    double mean = 0;
    for (const Vec2& p : c.centres) {
        EXPECT_LE(length(p), 1.0f);
        mean += length(p);
    }
    mean /= c.centres.size();
    EXPECT_NEAR(mean, num / den, 0.01);  // standard error ~0.005
    // Uniform density would put the mean at 2/3: the fall-off must show.
    EXPECT_LT(mean, 0.64);
}

TEST(PlyCrossSection, MigrationMovesFibersWithinTheirRange) {
    YarnDescription d = default_yarn_description();
    d.migration_rho_min = 0.6f;
    d.migration_rho_max = 1.0f;
    d.migration_rho_min = 0.6f;
    YarnDescription rest = d;
    rest.migration_rho_min = rest.migration_rho_max = 1;
    const Circles2D r = ply_fibers(rest, 0);
    const Circles2D a = ply_fibers(d, 0), b = ply_fibers(d, kPi);
    ASSERT_EQ(a.centres.size(), r.centres.size());
    int moved = 0;
    for (size_t i = 0; i < r.centres.size(); ++i) {
        const float r0 = length(r.centres[i]);
        for (const Circles2D* c : {&a, &b}) {
            const float ri = length(c->centres[i]);
            EXPECT_GE(ri, 0.6f * r0 - 1e-5f);
            EXPECT_LE(ri, r0 + 1e-5f);
            // Same direction as the rest position: fibers move radially.
            EXPECT_NEAR(dot(c->centres[i], r.centres[i]), ri * r0, 1e-4f);
        }
        moved += std::fabs(length(a.centres[i]) - length(b.centres[i])) > 0.05f * r0;
    }
    EXPECT_GT(moved, 10);
    // Deterministic for a seed, different for another.
    EXPECT_EQ(ply_fibers(d, 1.0f).centres[7].x, ply_fibers(d, 1.0f).centres[7].x);
    YarnDescription other = d;
    other.seed = 2;
    EXPECT_NE(ply_fibers(other, 1.0f).centres[7].x, ply_fibers(d, 1.0f).centres[7].x);
}

TEST(FiberMaps, SmallValidAndMatchingTheCrossSection) {
    const YarnDescription d = default_yarn_description();
    const FiberMaps maps(d);
    EXPECT_EQ(maps.variants(), 4);
    EXPECT_EQ(maps.resolution(), 256);
    EXPECT_LE(maps.memory_bytes(), 10u * 1024);
    float min_g = 1, max_g = 0;
    for (int v = 0; v < maps.variants(); ++v)
        for (int i = 0; i < 256; ++i) {
            const float angle = 2 * kPi * (i + 0.5f) / 256;
            const FiberSample s = maps.sample(v, angle);
            // A fiber seen from outside faces outward: within 90 degrees of the ply normal.
            EXPECT_LT(std::fabs(s.normal_angle), kPi / 2) << v << " " << i;
            EXPECT_GE(s.shadowing, 0.0f);
            EXPECT_LE(s.shadowing, 1.0f);
            min_g = std::min(min_g, s.shadowing);
            max_g = std::max(max_g, s.shadowing);
        }
    EXPECT_LT(min_g, 0.05f);  // normalised: the most occluded sample reaches 0
    EXPECT_GT(max_g, 0.5f);
    // At a bin centre the map holds exactly what a ray into the cross-section sees.
    const Circles2D fibers = ply_fibers(d, 0);
    for (int i : {3, 77, 200}) {
        const float angle = 2 * kPi * (i + 0.5f) / 256;
        const Vec2 radial(std::cos(angle), std::sin(angle));
        float t;
        const int k = fibers.first_hit(radial * (1 + 2 * d.fiber_radius), radial * -1.0f, 0, t);
        ASSERT_GE(k, 0);
        const Vec2 p = radial * (1 + 2 * d.fiber_radius - t);
        const Vec2 n = (p - fibers.centres[k]) * (1 / fibers.radius);
        const FiberSample s = maps.sample(0, angle);
        EXPECT_NEAR(s.normal_angle, std::atan2(radial.x * n.y - radial.y * n.x, dot(radial, n)), 1e-3f);
        EXPECT_NEAR(s.fiber_distance, length(fibers.centres[k]), 1e-3f);
        EXPECT_NEAR(std::remainder(s.fiber_phase - std::atan2(fibers.centres[k].y, fibers.centres[k].x), 2 * kPi),
                    0, 1e-3f);
    }
}

TEST(FiberMaps, MigrationBlendIsContinuousAndVaried) {
    const FiberMaps maps(default_yarn_description());
    const float angle = 1.234f;
    std::set<int> used;
    float worst_jump = 0;
    FiberSample previous = maps.lookup(angle, 0, 42);
    for (int i = 1; i <= 4000; ++i) {
        const float position = i * 0.005f;  // 20 cells
        const FiberSample s = maps.lookup(angle, position, 42);
        worst_jump = std::max(worst_jump, std::fabs(s.normal_angle - previous.normal_angle));
        worst_jump = std::max(worst_jump, std::fabs(s.shadowing - previous.shadowing));
        previous = s;
        used.insert(maps.variant_of(42, static_cast<int64_t>(std::floor(position))));
    }
    EXPECT_LT(worst_jump, 0.05f);  // no seam: a step of 1/200 cell moves at most 1.5 / 200 of a jump
    EXPECT_GE(used.size(), 3u);    // the variants do get used
    // A different ply (key) switches differently.
    int differ = 0;
    for (int c = 0; c < 20; ++c) differ += maps.variant_of(42, c) != maps.variant_of(43, c);
    EXPECT_GT(differ, 5);
    // Around a loop of 7 cells the end meets the start.
    const FiberSample end = maps.lookup(angle, 7 - 1e-4f, 42, 7), start = maps.lookup(angle, 0, 42, 7);
    EXPECT_NEAR(end.normal_angle, start.normal_angle, 1e-3f);
    EXPECT_NEAR(end.shadowing, start.shadowing, 1e-3f);
}

TEST(FiberMaps, PlyShadowingFollowsThePlyArrangement) {
    YarnDescription d = default_yarn_description();  // 3 touching plies
    const FiberMaps maps(d);
    // On top of a ply is open; the groove between two plies is the most shadowed.
    const float top = maps.ply_shadowing(0.0f), groove = maps.ply_shadowing(kPi / 3);
    EXPECT_GT(top, 0.9f);
    EXPECT_LT(groove, 0.1f);
    for (float a = 0; a < 2 * kPi / 3; a += 0.1f) {
        EXPECT_NEAR(maps.ply_shadowing(a), maps.ply_shadowing(a + 2 * kPi / 3), 0.02f);  // N-fold symmetric
        EXPECT_NEAR(maps.ply_shadowing(a), maps.ply_shadowing(-a), 0.02f);              // mirror symmetric
    }
    d.ply_count = 1;
    d.ply_distance = 0;
    d.ply_radius = 0.97f;
    const FiberMaps single(d);
    for (float a = 0; a < 6; a += 0.5f) EXPECT_EQ(single.ply_shadowing(a), 1.0f);
}

}  // namespace
}  // namespace purl
