// Rays spawned from Embree hits (math/ray_spawn.h) never find the surface they leave: flat
// planes and straight round curves (both convex from the side a ray leaves on, so any hit of
// a spawned ray is a self-intersection), at sizes from 1e-4 to 1e4 and up to 1e6 from the
// origin, with random incoming and outgoing directions. Hit points must also lie within their
// error bound of the true surface. Run under every Embree ISA by scripts/test.sh.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "math/frame.h"
#include "math/ray_spawn.h"
#include "scene/embree_scene.h"

namespace purl {
namespace {

struct Placement {
    float size, offset;
};

std::string placement_name(const testing::TestParamInfo<Placement>& info) {
    char name[64];
    std::snprintf(name, sizeof(name), "size_%g_moved_%g", info.param.size, info.param.offset);
    std::string s = name;
    for (char& c : s)
        if (c == '+' || c == '.' || c == '-') c = '_';
    return s;
}

Vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    return normalize(Vec3(g(rng), g(rng), g(rng)));
}

// A unit direction on the side of `n` given by `sign`, at least 1 degree off the surface.
Vec3 random_side(std::mt19937& rng, Vec3 n, float sign) {
    for (;;) {
        const Vec3 w = random_unit(rng);
        if (sign * dot(w, n) > 0.0175f) return w;
    }
}

constexpr int kRays = 4000;

class SpawnOnPlane : public testing::TestWithParam<Placement> {};

TEST_P(SpawnOnPlane, NoRayFindsThePlaneItLeaves) {
    const auto [width, offset] = GetParam();
    const Vec3 centre(offset), n = normalize(Vec3(1, 2, 3));
    Vec3 s, t;
    orthonormal_basis(n, s, t);
    const float half = 0.5f * width;
    SceneDesc scene;
    MeshDesc plane;
    plane.vertices = {centre - s * half - t * half, centre + s * half - t * half, centre + s * half + t * half,
                      centre - s * half + t * half};
    plane.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back(plane);
    const EmbreeScene geometry(scene);

    std::mt19937 rng(7);
    std::uniform_real_distribution<float> across(-0.4f, 0.4f);
    int hits = 0, self_hits = 0, off_surface = 0;
    for (int i = 0; i < kRays; ++i) {
        // Half of the points near the centre, half anywhere: a point near the world origin
        // on a wide plane is where an offset from the point's own magnitude fails.
        const float reach = i % 2 ? width : std::min(width, 2.0f);
        const Vec3 target = centre + s * (across(rng) * reach) + t * (across(rng) * reach);
        const float side = i % 4 < 2 ? 1.0f : -1.0f;
        const Vec3 from = random_side(rng, n, side);
        Ray ray;
        ray.origin = target + from * (0.1f * reach);
        ray.direction = -from;
        SurfaceHit hit;
        if (!geometry.intersect(ray, hit)) continue;
        ++hits;
        if (std::fabs(dot(hit.position - target, n)) > hit.error * 1.8f) ++off_surface;
        // Reflected (back where the ray came from) and transmitted (on through).
        for (float leave : {side, -side}) {
            Ray next;
            next.direction = random_side(rng, n, leave);
            next.origin = spawn_origin({hit.position, hit.geometric_normal, hit.error}, next.direction);
            SurfaceHit again;
            if (geometry.intersect(next, again)) ++self_hits;
        }
    }
    EXPECT_GT(hits, kRays * 9 / 10);
    EXPECT_EQ(self_hits, 0) << "of " << 2 * hits << " spawned rays";
    EXPECT_EQ(off_surface, 0);
}

INSTANTIATE_TEST_SUITE_P(Placements, SpawnOnPlane,
                         testing::Values(Placement{1e-4f, 0}, Placement{1, 0}, Placement{1e3f, 0}, Placement{1e4f, 0},
                                         Placement{200, 1e4f}, Placement{200, 1e6f}, Placement{1e4f, 1e6f}),
                         placement_name);

class SpawnOnCurve : public testing::TestWithParam<Placement> {};

// A straight round B-spline of radius `size` along a tilted axis: a convex capsule.
TEST_P(SpawnOnCurve, NoRayLeavingTheTubeFindsIt) {
    const auto [radius, offset] = GetParam();
    const Vec3 centre(offset), axis = normalize(Vec3(3, -1, 2));
    const Vec3 across = normalize(cross(axis, Vec3(0, 0, 1)));
    SceneDesc scene;
    YarnSetDesc yarn;
    std::vector<Vec4> points;
    for (int i = 0; i < 8; ++i) points.emplace_back(centre + axis * (radius * 3 * (i - 3.5f)), radius);
    yarn.curves.add_curve(points.data(), points.size(), false);
    scene.yarns.push_back(yarn);
    const EmbreeScene geometry(scene);

    std::mt19937 rng(11);
    std::uniform_real_distribution<float> along(-3, 3), around(0, 2 * kPi);
    int hits = 0, self_hits = 0, off_surface = 0, far_wall = 0;
    for (int i = 0; i < kRays; ++i) {
        const Vec3 on_axis = centre + axis * (along(rng) * radius);
        const float phi = around(rng);
        const Vec3 radial = across * std::cos(phi) + cross(axis, across) * std::sin(phi);
        const Vec3 from = random_side(rng, radial, 1.0f);
        Ray ray;
        ray.origin = on_axis + radial * radius + from * (4 * radius);
        ray.direction = -from;
        SurfaceHit hit;
        if (!geometry.intersect(ray, hit)) continue;
        // Embree now and then misses the entry where two segments meet (their control points
        // rounded off a straight line, the seam has a kink) and reports the far wall: counted.
        if (dot(ray.direction, hit.geometric_normal) >= 0) {
            ++far_wall;
            continue;
        }
        ++hits;
        Vec3 q = hit.position - centre;
        q -= axis * dot(q, axis);
        // The control points themselves are rounded to floats: their spacing near `centre`.
        const float grid = 2 * std::nextafter(offset, 2 * offset + 1) - 2 * offset;
        if (std::fabs(length(q) - radius) > hit.error * 1.8f + grid) ++off_surface;
        Ray next;
        next.direction = random_side(rng, hit.geometric_normal, 1.0f);
        next.origin = spawn_origin({hit.position, hit.geometric_normal, hit.error}, next.direction);
        SurfaceHit again;
        if (geometry.intersect(next, again)) ++self_hits;
    }
    EXPECT_GT(hits, kRays / 2);
    EXPECT_LE(far_wall, kRays / 1000);
    EXPECT_EQ(self_hits, 0) << "of " << hits << " spawned rays";
    EXPECT_EQ(off_surface, 0);
}

INSTANTIATE_TEST_SUITE_P(Placements, SpawnOnCurve,
                         testing::Values(Placement{1e-4f, 0}, Placement{1e-2f, 0}, Placement{1, 0}, Placement{1e3f, 0},
                                         Placement{1e-2f, 1e2f}, Placement{1, 1e4f}, Placement{10, 1e5f},
                                         Placement{100, 1e6f}),
                         placement_name);

TEST(ShadowRay, LightNearerThanTheOffsetIsNotOccluded) {
    const Vec3 p(1e6f, 0, 0), n(0, 0, 1);
    const Vec3 origin = spawn_origin({p, n, triangle_point_error(p, p, p)}, n);
    EXPECT_GT(origin.z, 0.0f);
    // A light 1e-3 above the point, below the offset (about 0.1 at 1e6).
    const ShadowRay near = shadow_ray_to_light(origin, p, n, 1e-3f);
    EXPECT_TRUE(near.empty);
    const ShadowRay far = shadow_ray_to_light(origin, p, n, 10.0f);
    EXPECT_FALSE(far.empty);
    EXPECT_NEAR(far.tmax, length(p + n * 10 - origin), 1e-3f);
    EXPECT_LT(far.tmax, length(p + n * 10 - origin));  // short of the light itself
    EXPECT_TRUE(std::isinf(shadow_ray_to_light(origin, p, n, INFINITY).tmax));
}

}  // namespace
}  // namespace purl
