// The one ray-cylinder test (math/ray_cylinder.h) and the fast sines (math/fast_trig.h).
#include <gtest/gtest.h>

#include <cmath>

#include "math/fast_trig.h"
#include "math/ray_cylinder.h"

namespace purl {
namespace {

TEST(RayCylinder, EntryExitAndChordOfATiltedRay) {
    // Cylinder of radius 2 around the z axis through (1, 0, 0); a ray from x = 10 toward -x,
    // tilted by 30 degrees toward +z, 1 above the axis: it crosses 2 sqrt(3) across the axis,
    // 4 along the ray.
    const Vec3 axis_point(1, 0, 5), axis(0, 0, 1);
    const Vec3 direction = normalize(Vec3(-std::cos(0.5236f), 0, std::sin(0.5236f)));
    const Vec3 origin(10, 1, 0);
    const RayCylinder r = ray_cylinder(origin, direction, axis_point, axis, 2.0f);
    ASSERT_FALSE(r.along_axis());
    EXPECT_GE(r.discriminant(), 0);
    const float across = std::cos(0.5236f);  // the ray's speed across the axis
    EXPECT_NEAR(r.entry(), (9 - std::sqrt(3.0f)) / across, 1e-4f);
    EXPECT_NEAR(r.exit(), (9 + std::sqrt(3.0f)) / across, 1e-4f);
    // From the entry, the chord is the way to the exit; from the axis, a radius and a bit.
    const RayCylinder inside = ray_cylinder(origin + direction * r.entry(), direction, axis_point, axis, 2.0f);
    EXPECT_NEAR(inside.chord(), 2 * std::sqrt(3.0f) / across, 1e-4f);
    const RayCylinder centre = ray_cylinder(Vec3(1, 0, 0), direction, axis_point, axis, 2.0f);
    EXPECT_NEAR(centre.chord(), 2 / across, 1e-5f);
}

TEST(RayCylinder, MissesGrazesAndRunsAlong) {
    const Vec3 axis(0, 0, 1);
    // Passing 3 from the axis of a radius-2 cylinder: a negative discriminant; entry() and
    // exit() then give the closest approach.
    const RayCylinder miss = ray_cylinder(Vec3(10, 3, 0), Vec3(-1, 0, 0), Vec3(0.0f), axis, 2.0f);
    EXPECT_LT(miss.discriminant(), 0);
    EXPECT_NEAR(miss.entry(), 10, 1e-5f);
    EXPECT_NEAR(miss.exit(), 10, 1e-5f);
    // An origin just outside the wall counts as on it for the chord (it leaves at once).
    const RayCylinder out = ray_cylinder(Vec3(2.0001f, 0, 0), Vec3(1, 0, 0), Vec3(0.0f), axis, 2.0f);
    EXPECT_GT(out.c, 0);
    EXPECT_NEAR(out.chord(), 0, 1e-6f);
    EXPECT_TRUE(ray_cylinder(Vec3(1, 0, 0), axis, Vec3(0.0f), axis, 2.0f).along_axis());
}

// The worst error of fast_sincos over [-limit, limit], against double precision.
float fast_sincos_error(float limit) {
    float worst = 0;
    for (int i = -20000; i <= 20000; ++i) {
        const float a = limit * float(i) / 20000;
        float c, s;
        fast_sincos(a, c, s);
        worst = std::max(worst, float(std::fabs(c - std::cos(double(a)))));
        worst = std::max(worst, float(std::fabs(s - std::sin(double(a)))));
    }
    return worst;
}

TEST(FastTrig, ErrorGrowsOnlyWithTheReduction) {
    // The polynomials are good to ~5e-7 on their quarter turn; beyond, the float product of
    // the quarter turns and pi/2's leading part rounds, by ~5e-8 of the angle.
    EXPECT_LT(fast_sincos_error(10), 6e-7f);
    EXPECT_LT(fast_sincos_error(1000), 4e-5f);
    EXPECT_LT(fast_sincos_error(1e4f), 6e-4f);
}

}  // namespace
}  // namespace purl
