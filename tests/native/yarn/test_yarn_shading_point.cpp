#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "yarn/straight_yarn.h"
#include "yarn/yarn_shading_point.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

struct Yarn {
    std::vector<Vec4> points = straight_yarn_points();
    CurveFrames frames{CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), false)};
};

YarnTubeHit hit_at(const CurveFrames& f, float offset, float psi, float z) {
    YarnTubeHit h;
    h.direction = normalize(Vec3(-std::cos(psi), 0, std::sin(psi)));
    h.point = Vec3(std::sqrt(1 - offset * offset), offset, z);
    h.origin = h.point - h.direction * 5.0f;
    const CentrelineProjection p = project_to_centreline(f, h.point, static_cast<uint32_t>(z), 0.5f);
    h.segment = p.segment;
    h.t = p.t;
    return h;
}

TEST(YarnShadingPoint, FiberFrameIsOrthonormalAndMapsAreInRange) {
    const Yarn y;
    const YarnDescription d = default_yarn_description();
    const FiberMaps maps(d);
    int hits = 0;
    for (int i = 0; i < 200; ++i) {
        const YarnTubeHit h = hit_at(y.frames, -0.95f + 0.0095f * i, 0.02f * (i % 40), 35 + 0.013f * i);
        const YarnShadingPoint sp = trace_yarn_hit(y.frames, d, maps, h, 3);
        ASSERT_TRUE(is_finite(sp.fiber_normal) && is_finite(sp.fiber_tangent) && is_finite(sp.position));
        if (!sp.hit) {
            EXPECT_GT(sp.exit_distance, 0.0f);
            continue;
        }
        ++hits;
        EXPECT_NEAR(length(sp.fiber_normal), 1, 1e-4f);
        EXPECT_NEAR(length(sp.fiber_tangent), 1, 1e-4f);
        EXPECT_NEAR(dot(sp.fiber_normal, sp.fiber_tangent), 0, 1e-4f);
        EXPECT_GE(sp.ply_shadowing, 0.0f);
        EXPECT_LE(sp.ply_shadowing, 1.0f);
        EXPECT_GE(sp.fiber_shadowing, 0.0f);
        EXPECT_LE(sp.fiber_shadowing, 1.0f);
        EXPECT_GE(sp.plies_crossed, 1);
        EXPECT_GE(sp.ply_index, 0);
        EXPECT_LT(sp.ply_index, 3);
        // Fibers lean from the ply by at most atan(fiber_twist * ply_radius * ~1.1).
        EXPECT_GT(dot(sp.fiber_tangent, sp.ply_tangent), std::cos(std::atan(d.fiber_twist * d.ply_radius * 1.2f)));
    }
    EXPECT_GT(hits, 150);
}

TEST(YarnShadingPoint, FiberTiltFollowsTheFiberTwist) {
    const Yarn y;
    YarnDescription d = default_yarn_description();
    d.fiber_twist = 0;  // fibers parallel to the ply: no tilt at all
    const FiberMaps flat_maps(d);
    const YarnTubeHit h = hit_at(y.frames, 0.2f, 0.3f, 38.0f);
    const YarnShadingPoint flat = trace_yarn_hit(y.frames, d, flat_maps, h, 0);
    ASSERT_TRUE(flat.hit);
    EXPECT_GT(dot(flat.fiber_tangent, flat.ply_tangent), 0.99999f);
    // The fiber normal is the ply normal turned by the map's angle about the ply tangent.
    d.fiber_twist = 1.5f;
    const FiberMaps maps(d);
    const YarnShadingPoint twisted = trace_yarn_hit(y.frames, d, maps, h, 0);
    const float tilt = std::acos(clamp(dot(twisted.fiber_tangent, twisted.ply_tangent), -1.0f, 1.0f));
    EXPECT_GT(tilt, 0.05f);
    EXPECT_LT(tilt, std::atan(1.5f * d.ply_radius * 1.2f));
    // The visible fiber sits near the hit, so it leans along the ply's azimuthal direction
    // t x n with the sign of the fiber handedness.
    for (float handedness : {1.0f, -1.0f}) {
        d.fiber_handedness = handedness;
        const FiberMaps m(d);
        int agree = 0, hits = 0;
        for (int i = 0; i < 100; ++i) {
            const YarnShadingPoint sp = trace_yarn_hit(y.frames, d, m, hit_at(y.frames, -0.9f + 0.018f * i, 0.4f, 36 + 0.02f * i), 0);
            if (!sp.hit) continue;
            ++hits;
            agree += dot(sp.fiber_tangent - sp.ply_tangent, cross(sp.ply_tangent, sp.ply_normal)) * handedness > 0;
        }
        EXPECT_GT(agree, 0.8 * hits) << handedness;
    }
}

TEST(YarnShadingPoint, PassThroughCarriesTheExitDistance) {
    const Yarn y;
    const YarnDescription d = default_yarn_description();
    const FiberMaps maps(d);
    // 0.99 R: outside the plies (0.97 R) but inside the tube.
    const YarnShadingPoint sp = trace_yarn_hit(y.frames, d, maps, hit_at(y.frames, 0.99f, 0.0f, 37.0f), 0);
    EXPECT_FALSE(sp.hit);
    EXPECT_NEAR(sp.exit_distance, 2 * std::sqrt(1 - 0.99f * 0.99f), 1e-3f);
    EXPECT_EQ(sp.plies_crossed, 0);
}

}  // namespace
}  // namespace purl
