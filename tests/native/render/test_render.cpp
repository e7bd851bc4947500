// End-to-end renders of tiny scenes: radiometry of a diffuse plane, determinism across
// thread counts, cancellation, passes.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "render/renderer.h"

using namespace purl;

namespace {

MeshDesc ground_plane(float half, Vec3 color) {
    MeshDesc m;
    m.vertices = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.color = color;
    return m;
}

// A camera 3 m above the origin looking straight down.
SceneDesc plane_scene(int size, int spp) {
    SceneDesc s;
    s.camera.to_world = Transform::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0});
    s.film.width = size;
    s.film.height = size;
    s.render.spp = spp;
    s.meshes.push_back(ground_plane(100.0f, Vec3(0.5f)));
    return s;
}

YarnSetDesc wavy_yarns() {
    YarnSetDesc y;
    for (int c = 0; c < 4; ++c) {
        std::vector<Vec4> pts;
        for (int i = 0; i < 12; ++i)
            pts.emplace_back(-0.6f + 0.12f * i, -0.3f + 0.2f * c, 0.1f + 0.05f * std::sin(1.3f * i + c), 0.06f);
        y.curves.add_curve(pts.data(), pts.size(), false);
    }
    y.material.placeholder = PlaceholderParams{};
    apply_defaults(y.material.placeholder, placeholder_param_table());
    return y;
}

double mean_channel(const RenderImage& image, const char* pass, int channel) {
    const ImagePass* p = image.find(pass);
    double sum = 0;
    const size_t n = size_t(image.width) * image.height;
    for (size_t i = 0; i < n; ++i) sum += p->pixels[i * p->channels() + channel];
    return sum / n;
}

}  // namespace

TEST(Render, DiffusePlaneUnderWhiteSkyHasItsAlbedo) {
    SceneDesc s = plane_scene(8, 256);
    s.world.color = Vec3(1.0f);
    Renderer r(s);
    RenderControl control;
    const RenderResult result = r.render(control);
    // Radiance = albedo * E / pi with E = pi for a unit sky over a horizontal plane.
    EXPECT_NEAR(mean_channel(result.image, "Combined", 0), 0.5, 0.01);
    EXPECT_NEAR(mean_channel(result.image, "Combined", 3), 1.0, 1e-6);
    EXPECT_EQ(result.stats.invalid_samples, 0u);
}

TEST(Render, DiffusePlaneUnderPointLightFollowsInverseSquare) {
    SceneDesc s = plane_scene(1, 64);  // one pixel, looking at the origin
    LightDesc light;
    light.type = LightType::Point;
    light.to_world = Transform::look_at({0, 0, 2}, {0, 0, 0}, {0, 1, 0});
    light.power = 1000;
    s.lights.push_back(light);
    s.camera.lens_mm = 5000;  // a narrow view, so the pixel sees the point under the light
    Renderer r(s);
    RenderControl control;
    const RenderResult result = r.render(control);
    const double expected = 0.5 / kPi * (1000 / (4 * kPi)) / 4.0;
    EXPECT_NEAR(mean_channel(result.image, "Combined", 1) / expected, 1.0, 0.01);
}

TEST(Render, PassesDescribeTheFirstHit) {
    SceneDesc s = plane_scene(16, 2);
    s.world.color = Vec3(1.0f);
    s.yarns.push_back(wavy_yarns());
    Renderer r(s);
    RenderControl control;
    const RenderResult result = r.render(control);
    const RenderImage& img = result.image;
    const ImagePass* depth = img.find("Depth");
    const ImagePass* normal = img.find("Normal");
    const ImagePass* id = img.find("YarnID");
    ASSERT_TRUE(depth && normal && id);
    int yarn_pixels = 0;
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
        if (id->pixels[i] > 0) {
            ++yarn_pixels;
            EXPECT_LT(depth->pixels[i], 3.0f);  // yarns sit above the plane
            EXPECT_GE(id->pixels[i], 1.0f);
            EXPECT_LE(id->pixels[i], 4.0f);
        } else {
            // Sample 0 saw the plane, 3 m along the view axis; other samples may have seen a yarn.
            EXPECT_LE(depth->pixels[i], 3.0f + 1e-3f);
            if (depth->pixels[i] > 3.0f - 1e-3f) {
                EXPECT_NEAR(normal->pixels[3 * i + 2], 1.0f, 1e-4f);
            }
        }
    }
    EXPECT_GT(yarn_pixels, 10);
}

TEST(Render, TransparentFilmAndHoldoutGiveZeroAlpha) {
    SceneDesc s = plane_scene(8, 4);
    s.film.transparent = true;
    s.meshes[0].holdout = true;
    s.world.color = Vec3(1.0f);
    Renderer r(s);
    RenderControl control;
    const RenderResult result = r.render(control);
    EXPECT_EQ(mean_channel(result.image, "Combined", 3), 0.0);
    EXPECT_EQ(mean_channel(result.image, "Combined", 0), 0.0);
}

TEST(Render, ImageDoesNotDependOnThreadCount) {
    SceneDesc s = plane_scene(40, 4);
    s.world.color = Vec3(0.3f);
    LightDesc light;
    light.type = LightType::Area;
    light.to_world = Transform::look_at({1, 1, 2}, {0, 0, 0}, {0, 0, 1});
    s.lights.push_back(light);
    s.yarns.push_back(wavy_yarns());
    Renderer r(s);
    RenderSettings one = s.render, two = s.render;
    one.threads = 1;
    two.threads = 2;
    RenderControl c1, c2, c3;
    const RenderResult a = r.render(one, c1), b = r.render(two, c2), again = r.render(two, c3);
    for (size_t p = 0; p < a.image.passes.size(); ++p) {
        EXPECT_EQ(a.image.passes[p].pixels, b.image.passes[p].pixels) << a.image.passes[p].name;
        EXPECT_EQ(b.image.passes[p].pixels, again.image.passes[p].pixels) << a.image.passes[p].name;
    }
    RenderSettings other_seed = two;
    other_seed.seed = 99;
    RenderControl c4;
    EXPECT_NE(r.render(other_seed, c4).image.passes[0].pixels, a.image.passes[0].pixels);
}

TEST(Render, CancelStopsPromptly) {
    SceneDesc s = plane_scene(256, 4096);  // minutes of work if not cancelled
    s.world.color = Vec3(1.0f);
    s.yarns.push_back(wavy_yarns());
    Renderer r(s);
    RenderControl control;
    uint64_t done_at_cancel = 0;
    std::thread canceller([&] {
        while (control.pixels_done.load() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        control.cancel = true;
        done_at_cancel = control.pixels_done.load();
    });
    const RenderResult result = r.render(control);
    canceller.join();
    EXPECT_TRUE(result.cancelled);
    // The render checks between pixels: each thread finishes at most the pixel it is in.
    // (Counted, not timed: a loaded machine cannot fail it; ctest's TIMEOUT catches a hang.)
    EXPECT_LE(control.pixels_done.load() - done_at_cancel, uint64_t(result.stats.threads));
    EXPECT_LT(control.progress(), 0.5);
}
