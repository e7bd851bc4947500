// Degenerate yarn curves: zero-length segments, curves collapsed to a point, curves that
// double back on themselves or pass through themselves, coils tighter than their radius.
// The readers accept them (they are valid geometry), so the renderer must finish a small
// image of them with finite pixels, through the BYSDF (curve frames, implicit plies) and
// the placeholder material.
#include <gtest/gtest.h>

#include <cmath>

#include "render/renderer.h"

using namespace purl;

namespace {

constexpr float kR = 0.02f;

std::vector<Vec4> points(std::initializer_list<Vec3> xyz, float radius = kR) {
    std::vector<Vec4> out;
    for (const Vec3& p : xyz) out.emplace_back(p, radius);
    return out;
}

// Every degenerate shape side by side, around the origin, about 1 m across; with
// `zero_length_loop`, also closed loops with zero-length segments (these once hung the
// renderer, see BysdfZeroLengthClosedLoopFinishes).
YarnCurves degenerate_curves(bool zero_length_loop) {
    YarnCurves c;
    auto add = [&](const std::vector<Vec4>& p, bool closed = false) { c.add_curve(p.data(), p.size(), closed); };
    // An ordinary curve, so the set has an extent.
    add(points({{-0.5f, -0.4f, 0}, {-0.2f, -0.35f, 0.05f}, {0.2f, -0.45f, 0}, {0.5f, -0.4f, 0.05f}}));
    // All control points equal: every segment has zero length.
    add(points({{0.0f, 0.0f, 0.1f}, {0.0f, 0.0f, 0.1f}, {0.0f, 0.0f, 0.1f}, {0.0f, 0.0f, 0.1f}, {0.0f, 0.0f, 0.1f}}));
    // Repeated points inside a curve: zero-length segments between ordinary ones.
    add(points({{-0.5f, 0.3f, 0}, {-0.3f, 0.3f, 0}, {-0.1f, 0.3f, 0}, {-0.1f, 0.3f, 0}, {-0.1f, 0.3f, 0},
                {-0.1f, 0.3f, 0}, {0.1f, 0.35f, 0}, {0.3f, 0.3f, 0}}));
    // Doubling back exactly: a cusp where the tangent flips.
    add(points({{-0.4f, 0.1f, 0}, {-0.2f, 0.1f, 0}, {0.0f, 0.1f, 0}, {-0.2f, 0.1f, 0}, {-0.4f, 0.1f, 0}}));
    // A figure eight crossing itself, closed.
    std::vector<Vec4> eight;
    for (int i = 0; i < 12; ++i) {
        const float t = 2 * kPi * i / 12;
        eight.emplace_back(0.3f + 0.15f * std::sin(t), 0.1f + 0.1f * std::sin(2 * t), 0.0f, kR);
    }
    add(eight, true);
    // A coil whose pitch and curvature radius are smaller than the yarn radius.
    std::vector<Vec4> coil;
    for (int i = 0; i < 40; ++i) {
        const float t = 1.3f * i;
        coil.emplace_back(-0.3f + 0.004f * i, -0.15f + 0.01f * std::cos(t), 0.01f * std::sin(t), kR);
    }
    add(coil);
    // A 1e-6 long open curve.
    add(points({{0.4f, -0.2f, 0}, {0.4f + 1e-6f, -0.2f, 0}, {0.4f + 2e-6f, -0.2f, 0}, {0.4f + 3e-6f, -0.2f, 0}}));
    if (zero_length_loop) {
        // The smallest closed chain, 3 identical points: zero speed everywhere on the loop.
        add(points({{0.2f, -0.2f, 0}, {0.2f, -0.2f, 0}, {0.2f, -0.2f, 0}}), true);
        // A closed loop with a zero-length stretch (4 equal points) between ordinary ones.
        add(points({{0.1f, -0.3f, 0}, {0.1f, -0.3f, 0}, {0.1f, -0.3f, 0}, {0.1f, -0.3f, 0}, {0.3f, -0.3f, 0},
                    {0.3f, -0.1f, 0}, {0.1f, -0.1f, 0}}),
            true);
    }
    return c;
}

SceneDesc degenerate_scene(const std::string& material, bool zero_length_loop = false) {
    SceneDesc s;
    s.camera.to_world = Transform::look_at({0, -0.3f, 1.5f}, {0, 0, 0}, {0, 0, 1});
    s.film.width = 24;
    s.film.height = 16;
    s.render.spp = 4;
    s.render.threads = 2;
    s.world.color = Vec3(0.5f);
    LightDesc sun;
    sun.type = LightType::Sun;
    sun.to_world = Transform::look_at({1, -1, 2}, {0, 0, 0}, {0, 0, 1});
    sun.strength = 3;
    s.lights.push_back(sun);
    YarnSetDesc y;
    y.curves = degenerate_curves(zero_length_loop);
    y.material.model = material == "placeholder" ? MaterialModel::Placeholder : MaterialModel::Bysdf;
    s.yarns.push_back(y);
    validate_curves(s.yarns[0].curves, "degenerate");  // the readers would accept these
    return s;
}

void expect_finite_image(const RenderResult& result) {
    for (const ImagePass& pass : result.image.passes)
        for (size_t i = 0; i < pass.pixels.size(); ++i)
            ASSERT_TRUE(std::isfinite(pass.pixels[i])) << pass.name << " value " << i;
    const ImagePass* combined = result.image.find("Combined");
    for (float v : combined->pixels) EXPECT_GE(v, 0.0f);
}

void render_and_check(const std::string& material, bool zero_length_loop = false) {
    const SceneDesc s = degenerate_scene(material, zero_length_loop);
    Renderer r(s);
    RenderControl control;
    const RenderResult result = r.render(control);
    expect_finite_image(result);
    // 384 pixels x 4 samples: a hang (a ray stuck between plies) runs into ctest's TIMEOUT.
    // Yarn pixels were seen at all (the camera looks at the curves).
    const ImagePass* id = result.image.find("YarnID");
    int yarn_pixels = 0;
    for (float v : id->pixels) yarn_pixels += v > 0;
    EXPECT_GT(yarn_pixels, 10);
    testing::Test::RecordProperty("invalid_samples", std::to_string(result.stats.invalid_samples));
    std::printf("%s: %.2f s, %llu of %llu samples invalid (dropped)\n", material.c_str(), result.stats.render_seconds,
                (unsigned long long)result.stats.invalid_samples, (unsigned long long)result.stats.samples);
}

}  // namespace

TEST(DegenerateCurves, BysdfRenderFinishesWithFinitePixels) { render_and_check("bysdf"); }

TEST(DegenerateCurves, PlaceholderRenderFinishesWithFinitePixels) { render_and_check("placeholder", true); }

// Once hung: on a zero-speed segment yarn_tube.cpp's project() stepped dt = ds / 1e-30 and
// CurveFrames::advance then looped `t += 1` on a closed loop with t near -1e28, which float
// cannot change. advance() now stops on non-finite or hopeless steps.
TEST(DegenerateCurves, BysdfZeroLengthClosedLoopFinishes) { render_and_check("bysdf", true); }

// Coordinates far from the origin (1e6 m) with a thin yarn: float precision is coarse there
// but nothing may turn into NaN or loop.
TEST(DegenerateCurves, FarFromTheOriginStillFinishes) {
    SceneDesc s = degenerate_scene("bysdf");
    for (Vec4& p : s.yarns[0].curves.control_points) p = Vec4(p.xyz() + Vec3(1e6f, 0, 0), p.w);
    s.camera.to_world = Transform::look_at({1e6f, -0.3f, 1.5f}, {1e6f, 0, 0}, {0, 0, 1});
    Renderer r(s);
    RenderControl control;
    expect_finite_image(r.render(control));
}
