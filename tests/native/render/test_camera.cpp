// The camera against Blender's view-plane formulas, worked out by hand for each case.
#include <gtest/gtest.h>

#include "render/camera.h"
#include "render/ray_cone.h"

using namespace purl;

namespace {

CameraDesc camera_at_origin() {
    CameraDesc c;  // identity placement: looks down -Z, +Y up, +X right
    c.lens_mm = 50;
    c.sensor_width_mm = 36;
    c.sensor_height_mm = 24;
    return c;
}

FilmDesc film(int w, int h, float ax = 1, float ay = 1) {
    FilmDesc f;
    f.width = w;
    f.height = h;
    f.pixel_aspect_x = ax;
    f.pixel_aspect_y = ay;
    return f;
}

// Blender: with horizontal fit the sensor width spans the image width, so a point at
// (X, Y, -Z) lands lens/sensor * X/Z image widths right of the centre.
void expect_projects(const Camera& cam, Vec3 p, float x, float y) {
    float px, py;
    ASSERT_TRUE(cam.project(p, px, py));
    EXPECT_NEAR(px, x, 1e-3f);
    EXPECT_NEAR(py, y, 1e-3f);
}

}  // namespace

TEST(Camera, HorizontalFitLandscape) {
    const Camera cam(camera_at_origin(), film(640, 480));
    expect_projects(cam, {0, 0, -5}, 320, 240);
    // 50/36 * (1/5) * 640 = 177.78 px right of centre.
    expect_projects(cam, {1, 0, -5}, 320 + 177.7778f, 240);
    expect_projects(cam, {0, 1, -5}, 320, 240 - 177.7778f);
}

TEST(Camera, AutoFitPortraitUsesSensorWidthForHeight) {
    const Camera cam(camera_at_origin(), film(480, 640));
    // Portrait: the 36 mm sensor width spans the 640 px height.
    expect_projects(cam, {1, 0, -5}, 240 + 177.7778f, 320);
}

TEST(Camera, VerticalFitUsesSensorHeight) {
    CameraDesc desc = camera_at_origin();
    desc.sensor_fit = SensorFit::Vertical;
    const Camera cam(desc, film(640, 480));
    // 24 mm spans 480 px: 50/24 * 0.2 * 480 = 200 px.
    expect_projects(cam, {1, 0, -5}, 320 + 200, 240);
    expect_projects(cam, {0, 1, -5}, 320, 240 - 200);
}

TEST(Camera, HorizontalFitPortraitKeepsWidth) {
    CameraDesc desc = camera_at_origin();
    desc.sensor_fit = SensorFit::Horizontal;
    const Camera cam(desc, film(480, 640));
    expect_projects(cam, {1, 0, -5}, 240 + 50.0f / 36 * 0.2f * 480, 320);
}

TEST(Camera, ShiftIsInUnitsOfTheLargerSide) {
    CameraDesc desc = camera_at_origin();
    desc.shift_x = 0.1f;
    desc.shift_y = -0.05f;
    const Camera cam(desc, film(640, 480));
    // Shifting the lens right moves the image content left by shift * 640 px.
    expect_projects(cam, {0, 0, -5}, 320 - 64, 240 - 32);
}

TEST(Camera, PixelAspectStretchesVertically) {
    CameraDesc desc = camera_at_origin();
    desc.sensor_fit = SensorFit::Horizontal;
    const Camera cam(desc, film(640, 480, 1, 2));
    // Pixels twice as tall: the same angle covers half as many rows.
    expect_projects(cam, {0, 1, -5}, 320, 240 - 177.7778f / 2);
}

TEST(Camera, RaysRoundTripAndCarryDifferentials) {
    CameraDesc desc = camera_at_origin();
    desc.to_world = Transform::look_at({3, -4, 2}, {0, 0, 0.5f}, {0, 0, 1});
    desc.shift_x = 0.03f;
    const Camera cam(desc, film(320, 200));
    for (float x : {0.5f, 100.25f, 319.5f})
        for (float y : {0.5f, 77.0f, 199.5f}) {
            const Ray r = cam.generate_ray(x, y);
            EXPECT_NEAR(length(r.direction), 1.0f, 1e-5f);
            float px, py;
            ASSERT_TRUE(cam.project(r.at(7.0f), px, py));
            EXPECT_NEAR(px, x, 1e-3f);
            EXPECT_NEAR(py, y, 1e-3f);
            ASSERT_TRUE(r.has_differentials);
            ASSERT_TRUE(cam.project(r.rx_origin + r.rx_direction * 7.0f, px, py));
            EXPECT_NEAR(px, x + 1, 1e-3f);
            ASSERT_TRUE(cam.project(r.ry_origin + r.ry_direction * 7.0f, px, py));
            EXPECT_NEAR(py, y + 1, 1e-3f);
        }
}

TEST(Camera, ClippingIsAlongTheViewAxis) {
    CameraDesc desc = camera_at_origin();
    desc.clip_start = 1.0f;
    desc.clip_end = 10.0f;
    const Camera cam(desc, film(640, 480));
    const Ray corner = cam.generate_ray(0, 0);
    EXPECT_NEAR(cam.view_depth(corner.at(corner.tmin)), 1.0f, 1e-5f);
    EXPECT_NEAR(cam.view_depth(corner.at(corner.tmax)), 10.0f, 1e-4f);
}

TEST(Camera, BehindTheCameraDoesNotProject) {
    const Camera cam(camera_at_origin(), film(64, 64));
    float x, y;
    EXPECT_FALSE(cam.project({0, 0, 1}, x, y));
}

TEST(Camera, PixelAspectChangesAutoFit) {
    // 640 x 480 with pixels twice as tall is 640 x 960 in shape: AUTO fits vertically and
    // the sensor width spans the (corrected) height.
    const Camera cam(camera_at_origin(), film(640, 480, 1, 2));
    expect_projects(cam, {1, 0, -5}, 320 + 50.0f / 36 * 0.2f * 960, 240);
}

// The ray cone starts one pixel wide in angle: 36 mm over 640 px at 50 mm is 1.125e-3 rad at the
// centre. Scattering off a cylinder of radius R adds 2 w / R to its spread.
TEST(RayCone, StartsAtOnePixelAndCurvedSurfacesSpreadIt) {
    const Camera cam(camera_at_origin(), film(640, 480));
    RayCone cone = RayCone::from_camera(cam.generate_ray(320, 240));
    EXPECT_NEAR(cone.spread, 36.0f / 50.0f / 640.0f, 1e-6f);
    EXPECT_EQ(cone.width, 0.0f);
    EXPECT_NEAR(cone.width_at(4.0f), 4.0f * cone.spread, 1e-7f);
    const float spread = cone.spread;
    cone.scatter(4.0f, 1.0f / 0.01f);  // a 1 cm tube, 4 m away
    EXPECT_NEAR(cone.width, 4.0f * spread, 1e-7f);
    EXPECT_NEAR(cone.spread, spread + 2 * cone.width / 0.01f, 1e-5f);
    cone.scatter(1.0f, 0.0f);  // a plane keeps the angle
    EXPECT_NEAR(cone.spread, spread + 2 * 4.0f * spread / 0.01f, 1e-5f);
    Ray no_differentials;
    EXPECT_EQ(RayCone::from_camera(no_differentials).spread, 0.0f);
}
