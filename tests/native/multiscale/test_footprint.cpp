// Footprint in h against hand-worked geometry: Blender's camera at a known distance from a
// straight yarn, so one pixel spans pixel_width / R in h (h runs over 2R for -1..1).
#include <gtest/gtest.h>

#include <cmath>

#include "math/transform.h"
#include "render/camera.h"
#include "render/footprint.h"

namespace purl {
namespace {

constexpr float kDistance = 2.0f;  // m, camera to yarn axis
constexpr float kRadius = 0.01f;   // m

// 50 mm lens, 36 mm sensor, 640 px wide: a pixel is 36 / 50 / 640 of the distance.
float pixel_width(float distance) { return distance * (36.0f / 50.0f) / 640.0f; }

Camera camera_at(float distance) {
    CameraDesc c;
    c.to_world = Transform::look_at(Vec3(0, 0, distance), Vec3(0, 0, 0), Vec3(0, 1, 0));
    c.clip_end = 1e5f;
    FilmDesc f;
    f.width = 640;
    f.height = 480;
    return Camera(c, f);
}

// Straight yarn through `centre` along `tangent`: where the ray enters it, and the axis point.
bool hit_yarn(const Ray& ray, Vec3 centre, Vec3 tangent, Vec3& hit, CurvePoint& axis) {
    const Vec3 w = ray.origin - centre;
    const Vec3 wp = w - tangent * dot(w, tangent), dp = ray.direction - tangent * dot(ray.direction, tangent);
    const float a = dot(dp, dp), b = dot(wp, dp), c = dot(wp, wp) - kRadius * kRadius;
    const float disc = b * b - a * c;
    if (disc < 0) return false;
    hit = ray.at((-b - std::sqrt(disc)) / a);
    axis = CurvePoint{};
    axis.position = centre + tangent * dot(hit - centre, tangent);
    axis.tangent = tangent;
    axis.radius = kRadius;
    return true;
}

AzimuthalFootprint footprint_of(const Camera& cam, float px, float py, Vec3 centre, Vec3 tangent, float scale = 1) {
    const Ray ray = cam.generate_ray(px, py);
    Vec3 hit;
    CurvePoint axis;
    EXPECT_TRUE(hit_yarn(ray, centre, tangent, hit, axis));
    return yarn_footprint(ray, hit, axis, scale);
}

TEST(Footprint, HorizontalYarnSpansPixelWidthOverRadius) {
    const Camera cam = camera_at(kDistance);
    const AzimuthalFootprint f = footprint_of(cam, 320.0f, 240.0f, Vec3(0.0f), Vec3(1, 0, 0));
    ASSERT_TRUE(f.valid);
    const float expected = pixel_width(kDistance) / kRadius;  // 0.225
    EXPECT_NEAR(f.width(), expected, 1e-3f * expected);
    EXPECT_NEAR(f.h0, 0.0f, 1e-4f);
    EXPECT_NEAR(f.h1, -0.5f * expected, 1e-3f);
    EXPECT_NEAR(f.h2, 0.5f * expected, 1e-3f);
    EXPECT_NEAR(f.raw_width, f.width(), 1e-6f);
    // A scale of 1/4 pixel quarters it.
    const AzimuthalFootprint q = footprint_of(cam, 320.0f, 240.0f, Vec3(0.0f), Vec3(1, 0, 0), 0.25f);
    EXPECT_NEAR(q.width(), 0.25f * expected, 1e-3f * expected);
}

TEST(Footprint, DiagonalYarnSpansTheProjectedBoxPixel) {
    // A square pixel seen across a 45 degree yarn is sqrt(2) pixel widths wide.
    const Camera cam = camera_at(kDistance);
    const AzimuthalFootprint f = footprint_of(cam, 320.0f, 240.0f, Vec3(0.0f), normalize(Vec3(1, 1, 0)));
    const float expected = std::sqrt(2.0f) * pixel_width(kDistance) / kRadius;
    EXPECT_NEAR(f.width(), expected, 2e-3f * expected);
}

TEST(Footprint, MeasuredInTheAzimuthalPlaneNotOnTheSurface) {
    const Camera cam = camera_at(kDistance);
    const float expected = pixel_width(kDistance) / kRadius;
    // A yarn tilted toward the camera by 60 degrees: the pixel still spans the same h.
    for (float tilt_deg : {30.0f, 60.0f, 80.0f}) {
        const float a = tilt_deg * kPi / 180;
        const AzimuthalFootprint f =
            footprint_of(cam, 320.0f, 240.0f, Vec3(0.0f), Vec3(std::cos(a), 0, std::sin(a)));
        EXPECT_NEAR(f.width(), expected, 2e-3f * expected) << tilt_deg;
    }
    // Near the silhouette (h0 = 0.85) the tube surface is seen at cos 0.53, yet the footprint
    // in h is the same as in the middle.
    const AzimuthalFootprint edge = footprint_of(cam, 320.0f, 240.0f, Vec3(0, 0.85f * kRadius, 0), Vec3(1, 0, 0));
    EXPECT_NEAR(std::fabs(edge.h0), 0.85f, 1e-3f);
    EXPECT_NEAR(edge.width(), expected, 2e-3f * expected);
}

TEST(Footprint, OffsetSignMatchesTheHitPoint) {
    // Seen from the side, the hit's own offset along `across` is h0 R.
    const Camera cam = camera_at(kDistance);
    for (float y : {-0.7f, -0.2f, 0.4f, 0.95f}) {
        const Ray ray = cam.generate_ray(320.0f, 240.0f);
        Vec3 hit;
        CurvePoint axis;
        ASSERT_TRUE(hit_yarn(ray, Vec3(0, y * kRadius, 0), Vec3(1, 0, 0), hit, axis));
        const AzimuthalFootprint f = yarn_footprint(ray, hit, axis);
        EXPECT_NEAR(dot(hit - axis.position, f.across) / kRadius, f.h0, 1e-3f) << y;
        EXPECT_NEAR(std::fabs(f.h0), std::fabs(y), 1e-3f) << y;
        EXPECT_NEAR(dot(f.across, axis.tangent), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(f.across, ray.direction), 0.0f, 1e-6f);
    }
}

TEST(Footprint, DistantYarnIsCoveredWhole) {
    // At 100 m one pixel is 0.1125 m: 11.25 in h, clamped to the yarn.
    const Camera cam = camera_at(100.0f);
    const AzimuthalFootprint f = footprint_of(cam, 320.0f, 240.0f, Vec3(0.0f), Vec3(1, 0, 0));
    EXPECT_TRUE(f.covers_yarn());
    EXPECT_EQ(f.h1, -1.0f);
    EXPECT_EQ(f.h2, 1.0f);
    EXPECT_NEAR(f.raw_width, pixel_width(100.0f) / kRadius, 1e-2f);
}

TEST(Footprint, FootprintIsClampedAtTheSilhouette) {
    const Camera cam = camera_at(kDistance * 4);  // 0.9 in h
    const AzimuthalFootprint f = footprint_of(cam, 320.0f, 240.0f, Vec3(0, 0.8f * kRadius, 0), Vec3(1, 0, 0));
    EXPECT_NEAR(f.raw_width, 0.9f, 2e-3f);
    EXPECT_TRUE(f.h1 == -1.0f || f.h2 == 1.0f);
    EXPECT_NEAR(f.width(), 0.2f + 0.45f, 2e-3f);  // from |h0| - 0.45 to the edge
    EXPECT_FALSE(f.covers_yarn());
}

TEST(Footprint, DegenerateCasesAreDefined) {
    CurvePoint axis{};
    axis.position = Vec3(0.0f);
    axis.tangent = Vec3(0, 0, 1);
    axis.radius = 1;
    // No differentials: the ray's own h only.
    Ray r;
    r.origin = Vec3(5, 0.3f, 0);
    r.direction = Vec3(-1, 0, 0);
    AzimuthalFootprint f = yarn_footprint(r, Vec3(std::sqrt(1 - 0.09f), 0.3f, 0), axis);
    EXPECT_FALSE(f.valid);
    EXPECT_FALSE(f.along_yarn);
    EXPECT_NEAR(std::fabs(f.h0), 0.3f, 1e-6f);
    EXPECT_EQ(f.h1, f.h0);
    EXPECT_EQ(f.h2, f.h0);
    // A ray exactly along the yarn: h is undefined; h0 = 0 and `across` still a unit vector
    // perpendicular to the yarn, toward the hit.
    r.origin = Vec3(0.5f, 0, -5);
    r.direction = Vec3(0, 0, 1);
    r.has_differentials = true;
    r.rx_origin = r.origin + Vec3(0.01f, 0, 0);
    r.ry_origin = r.origin + Vec3(0, 0.01f, 0);
    r.rx_direction = r.ry_direction = r.direction;
    f = yarn_footprint(r, Vec3(1, 0, 0), axis);
    EXPECT_FALSE(f.valid);
    EXPECT_TRUE(f.along_yarn);
    EXPECT_EQ(f.width(), 0.0f);
    EXPECT_NEAR(length(f.across), 1.0f, 1e-6f);
    EXPECT_NEAR(f.across.x, 1.0f, 1e-6f);
    // Grazing, 2 degrees from the yarn: still defined and the parallel offsets still count.
    r.direction = normalize(Vec3(-std::sin(2 * kPi / 180), 0, std::cos(2 * kPi / 180)));
    r.origin = Vec3(0, 0.25f, 0) - r.direction * 10.0f;
    r.rx_origin = r.origin + Vec3(0, 0.1f, 0);
    r.ry_origin = r.origin + Vec3(0, 0, 0.1f);
    r.rx_direction = r.ry_direction = r.direction;
    f = yarn_footprint(r, Vec3(0, 0.25f, 0), axis);
    EXPECT_TRUE(f.valid);
    EXPECT_NEAR(std::fabs(f.h0), 0.25f, 1e-4f);
    EXPECT_NEAR(f.width(), 0.1f, 1e-4f);  // the along-yarn offset adds nothing
    // A differential parallel to the silhouette plane (it never crosses it): no footprint.
    r.rx_direction = Vec3(0, 1, 0);
    f = yarn_footprint(r, Vec3(0, 0.25f, 0), axis);
    EXPECT_FALSE(f.valid);
    EXPECT_TRUE(std::isfinite(f.h0));
    // NaN input never gives NaN ranges.
    r.direction = Vec3(std::nanf(""), 0, 0);
    f = yarn_footprint(r, Vec3(0.0f), axis);
    EXPECT_FALSE(f.valid);
    EXPECT_TRUE(std::isfinite(f.h1) && std::isfinite(f.h2));
}

}  // namespace
}  // namespace purl
