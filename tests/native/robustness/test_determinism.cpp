// The image is a function of (scene, seed, spp): bit for bit the same for 1 and 2 threads
// and across separately built renderers, for BYSDF yarns (implicit plies, fiber maps,
// pass-through between plies), on a generated knit and on the glove.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "render/renderer.h"
#include "scene/bcc.h"
#include "scene/swatch.h"

using namespace purl;

namespace {

SceneDesc lit_scene(YarnCurves curves, Vec3 eye, Vec3 target, int width, int height, int spp) {
    SceneDesc s;
    s.camera.to_world = Transform::look_at(eye, target, {0, 0, 1});
    s.film.width = width;
    s.film.height = height;
    s.render.spp = spp;
    s.render.seed = 5;
    s.world.color = Vec3(0.2f, 0.25f, 0.3f);
    LightDesc area;
    area.type = LightType::Area;
    area.to_world = Transform::look_at(target + Vec3(1, -1, 2) * length(eye - target), target, {0, 0, 1});
    area.size = 0.5f * length(eye - target);
    area.power = 200.0f * length(eye - target) * length(eye - target);
    s.lights.push_back(area);
    YarnSetDesc y;
    y.curves = std::move(curves);
    y.material.model = MaterialModel::Bysdf;  // the default material: prototype plies and fibers
    s.yarns.push_back(std::move(y));
    return s;
}

// Renders with 1 thread, 2 threads and a second renderer built from scratch.
void expect_bit_identical(const SceneDesc& s) {
    RenderSettings one = s.render, two = s.render;
    one.threads = 1;
    two.threads = 2;
    Renderer first(s);
    RenderControl c1, c2, c3;
    const RenderResult a = first.render(one, c1);
    const RenderResult b = first.render(two, c2);
    Renderer second(s);
    const RenderResult again = second.render(two, c3);
    ASSERT_EQ(a.image.passes.size(), b.image.passes.size());
    double sum = 0;
    for (size_t p = 0; p < a.image.passes.size(); ++p) {
        const auto& pa = a.image.passes[p].pixels;
        // Bitwise: memcmp-equal, so -0/+0 or NaN payload differences would count too.
        ASSERT_EQ(pa.size(), b.image.passes[p].pixels.size());
        EXPECT_EQ(0, std::memcmp(pa.data(), b.image.passes[p].pixels.data(), pa.size() * sizeof(float)))
            << a.image.passes[p].name << ": 1 vs 2 threads";
        EXPECT_EQ(0, std::memcmp(pa.data(), again.image.passes[p].pixels.data(), pa.size() * sizeof(float)))
            << a.image.passes[p].name << ": second renderer";
    }
    for (float v : a.image.find("Combined")->pixels) sum += v;
    EXPECT_GT(sum, 0.0);  // the comparison is of a lit image, not of black ones
    EXPECT_GT(a.stats.samples, 0u);
}

}  // namespace

TEST(Determinism, BysdfKnitSwatchIsBitIdenticalAcrossThreadsAndRuns) {
    SwatchOptions options;
    options.courses = 4;
    options.wales = 3;
    const SceneDesc s = lit_scene(generate_swatch(SwatchKind::Knit, options), {0.0f, -0.01f, 0.03f}, {0, 0, 0}, 32, 24, 4);
    expect_bit_identical(s);
}

TEST(Determinism, BysdfGloveIsBitIdenticalAcrossThreadsAndRuns) {
    const std::string path = std::string(PURL_SHARED_DATA_DIR) + "/glove.bcc";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no shared data at " << path;
    // Radius 0.12: neighbouring yarns about touch (median point spacing 0.24, REFERENCE.md).
    YarnCurves glove = load_bcc(path, 0.12f);
    Vec3 lo(1e30f), hi(-1e30f);
    for (const Vec4& p : glove.control_points) {
        lo = min(lo, p.xyz());
        hi = max(hi, p.xyz());
    }
    const Vec3 centre = (lo + hi) * 0.5f;
    const SceneDesc s = lit_scene(std::move(glove), centre + Vec3(0, -45, 10), centre, 24, 24, 2);
    expect_bit_identical(s);
}
