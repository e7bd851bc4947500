// Light sampling: every pdf integrates to one over the sphere, light sampling and plain
// direction sampling estimate the same irradiance, and Cycles' radiometry holds
// (point: P/(4 pi d^2), area: 0.25 P/d^2 for a small light, sun: its strength).
#include <gtest/gtest.h>

#include <filesystem>

#include "io/image_io.h"
#include "math/rng.h"
#include "render/lights.h"

using namespace purl;

namespace {

constexpr int kSamples = 400000;

SceneDesc scene_with(const LightDesc& light) {
    SceneDesc s;
    s.lights.push_back(light);
    return s;
}

LightDesc light_above(LightType type, float height) {
    LightDesc l;
    l.type = type;
    l.to_world = Transform::look_at({0, 0, height}, {0, 0, 0}, {0, 1, 0});  // shines down -Z
    l.power = 100;
    return l;
}

// Radiance and light-sampling pdf seen from `p` along `d` (0 when nothing emits there).
void seen_along(const Lights& lights, Vec3 p, Vec3 d, Vec3& radiance, float& pdf) {
    Ray ray;
    ray.origin = p;
    ray.direction = d;
    EmitterHit hit;
    radiance = Vec3(0.0f);
    pdf = 0;
    if (lights.intersect_emitter(ray, 1e30f, hit)) {
        radiance = hit.radiance;
        pdf = hit.pdf;
        return;
    }
    lights.for_each_escaped(d, [&](const EmitterHit& e) {
        radiance += e.radiance;
        pdf += e.pdf;
    });
}

struct Estimates {
    double pdf_integral = 0;      // by uniform sphere sampling
    double irradiance_uniform = 0;
    double irradiance_light = 0;  // by light sampling
};

// Irradiance on a surface at the origin facing +Z, estimated two ways.
Estimates estimate(const Lights& lights) {
    Estimates e;
    Rng rng(7);
    const Vec3 p(0, 0, 0), n(0, 0, 1);
    for (int i = 0; i < kSamples; ++i) {
        const Vec3 d = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        Vec3 L;
        float pdf;
        seen_along(lights, p, d, L, pdf);
        e.pdf_integral += pdf / uniform_sphere_pdf();
        e.irradiance_uniform += average(L) * std::max(0.0f, dot(d, n)) / uniform_sphere_pdf();
        LightSample ls;
        if (lights.sample(p, rng.next_float(), {rng.next_float(), rng.next_float()}, ls) && ls.pdf > 0)
            e.irradiance_light += average(ls.radiance) * std::max(0.0f, dot(ls.wi, n)) / ls.pdf;
    }
    e.pdf_integral /= kSamples;
    e.irradiance_uniform /= kSamples;
    e.irradiance_light /= kSamples;
    return e;
}

}  // namespace

TEST(Lights, SphereLightMatchesPointLightIrradiance) {
    LightDesc l = light_above(LightType::Point, 2.0f);
    l.radius = 0.8f;  // large enough that uniform direction sampling sees it often
    const Lights lights(scene_with(l));
    const Estimates e = estimate(lights);
    const double expected = 100.0 / (4 * kPi * 4.0);  // P / (4 pi d^2)
    EXPECT_NEAR(e.pdf_integral, 1.0, 0.03);
    EXPECT_NEAR(e.irradiance_light / expected, 1.0, 0.01);
    EXPECT_NEAR(e.irradiance_uniform / expected, 1.0, 0.05);
}

TEST(Lights, PointLightWithoutRadiusIsDelta) {
    const Lights lights(scene_with(light_above(LightType::Point, 2.0f)));
    LightSample ls;
    ASSERT_TRUE(lights.sample({0, 0, 0}, 0.5f, {0.5f, 0.5f}, ls));
    EXPECT_TRUE(ls.delta);
    EXPECT_NEAR(average(ls.radiance) / ls.pdf, 100.0 / (4 * kPi * 4.0), 1e-5);
}

TEST(Lights, SpotConeCutsOffOutside) {
    LightDesc l = light_above(LightType::Spot, 1.0f);
    l.spot_size = 0.5f;  // half angle 0.25 rad
    l.spot_blend = 0.0f;
    const Lights lights(scene_with(l));
    LightSample inside, outside;
    ASSERT_TRUE(lights.sample({0.2f, 0, 0}, 0.5f, {0.5f, 0.5f}, inside));   // 11 deg off axis
    ASSERT_TRUE(lights.sample({0.3f, 0, 0}, 0.5f, {0.5f, 0.5f}, outside));  // 17 deg off axis
    EXPECT_GT(average(inside.radiance), 0.0f);
    EXPECT_EQ(average(outside.radiance), 0.0f);
}

// A spot with a radius: the cone is evaluated along the ray toward the shading point (Cycles 4.x),
// so a ray grazing the sphere's rim sees the same cone factor as one through its centre. It used
// to take the sphere's surface normal at the hit, which dimmed the blend region (-2% vs Cycles).
TEST(Lights, SpotSphereConeFollowsTheRayNotTheSurfaceNormal) {
    LightDesc l = light_above(LightType::Spot, 1.0f);
    l.radius = 0.05f;
    l.spot_size = 1.0f;   // half angle 0.5 rad
    l.spot_blend = 0.5f;  // blend region from about 0.34 to 0.5 rad
    const Lights lights(scene_with(l));
    const Vec3 p(0.45f, 0, 0);  // 0.42 rad off the axis: inside the blend
    Vec3 centre_radiance, rim_radiance;
    float pdf = 0;
    seen_along(lights, p, normalize(Vec3(0, 0, 1) - p), centre_radiance, pdf);
    seen_along(lights, p, normalize(Vec3(0, 0.045f, 1) - p), rim_radiance, pdf);
    ASSERT_GT(average(centre_radiance), 0.0f);
    // The blend is steep here: 0.04 rad between the two rays moves the factor a few percent
    // (the surface normal at the rim is 1.2 rad off and gave 0).
    EXPECT_NEAR(average(rim_radiance) / average(centre_radiance), 1.0, 0.06);
    LightSample ls;  // light sampling sees what a ray along the sampled direction sees
    ASSERT_TRUE(lights.sample(p, 0.5f, {0.3f, 0.7f}, ls));
    Vec3 along_sample;
    seen_along(lights, p, ls.wi, along_sample, pdf);
    EXPECT_NEAR(average(ls.radiance) / average(along_sample), 1.0, 1e-4);
}

TEST(Lights, SmallAreaLightGivesQuarterPowerOverDistanceSquared) {
    LightDesc l = light_above(LightType::Area, 10.0f);
    l.size = 0.5f;
    const Lights lights(scene_with(l));
    const Estimates e = estimate(lights);
    const double expected = 0.25 * 100.0 / 100.0;  // radiance 0.25 P / A times solid angle A / d^2
    EXPECT_NEAR(e.irradiance_light / expected, 1.0, 0.01);
}

TEST(Lights, AreaShapesIntegrateAndAgree) {
    for (AreaShape shape : {AreaShape::Square, AreaShape::Rectangle, AreaShape::Disk, AreaShape::Ellipse}) {
        LightDesc l = light_above(LightType::Area, 1.0f);
        l.shape = shape;
        l.size = 1.5f;
        l.size_y = 0.7f;
        l.to_world.m[0][3] = 0.4f;  // off-centre, so cosines vary across the light
        const Lights lights(scene_with(l));
        const Estimates e = estimate(lights);
        EXPECT_NEAR(e.pdf_integral, 1.0, 0.03) << int(shape);
        EXPECT_NEAR(e.irradiance_uniform / e.irradiance_light, 1.0, 0.03) << int(shape);
    }
}

TEST(Lights, AreaLightIsOneSided) {
    const Lights lights(scene_with(light_above(LightType::Area, 1.0f)));
    LightSample ls;
    EXPECT_FALSE(lights.sample({0, 0, 2}, 0.5f, {0.5f, 0.5f}, ls));  // above the light, behind it
}

TEST(Lights, SunIrradianceEqualsStrength) {
    for (float angle : {0.0f, 0.1f, 0.5f}) {
        LightDesc l = light_above(LightType::Sun, 1.0f);
        l.strength = 3.0f;
        l.angle = angle;
        const Lights lights(scene_with(l));
        const Estimates e = estimate(lights);
        // A disc of angular radius a gives E = L pi sin^2 a exactly on the axis.
        EXPECT_NEAR(e.irradiance_light / 3.0, 1.0, 0.01) << angle;
        if (angle > 0.3f) {
            EXPECT_NEAR(e.pdf_integral, 1.0, 0.05) << angle;
        }
    }
}

TEST(Lights, ConstantWorldGivesPiTimesRadiance) {
    SceneDesc s;
    s.world.color = Vec3(0.5f, 0.25f, 1.0f);
    s.world.strength = 2.0f;
    const Lights lights(s);
    const Estimates e = estimate(lights);
    const double expected = kPi * average(s.world.color) * 2.0;
    EXPECT_NEAR(e.pdf_integral, 1.0, 0.01);
    EXPECT_NEAR(e.irradiance_light / expected, 1.0, 0.02);
    EXPECT_NEAR(e.irradiance_uniform / expected, 1.0, 0.02);
}

TEST(Lights, WorldTextureIsImportanceSampledConsistently) {
    // A dim lat-long map with one bright blob: the sampled pdf must follow the map and
    // still integrate to one, and both estimators must agree.
    const int w = 64, h = 32;
    RenderImage img;
    img.width = w;
    img.height = h;
    ImagePass pass{"Combined", {"R", "G", "B", "A"}, std::vector<float>(size_t(w) * h * 4)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool blob = std::abs(x - 40) < 4 && std::abs(y - 10) < 3;
            for (int c = 0; c < 3; ++c) pass.pixels[(size_t(y) * w + x) * 4 + c] = blob ? 50.0f : 0.2f;
            pass.pixels[(size_t(y) * w + x) * 4 + 3] = 1.0f;
        }
    img.passes.push_back(pass);
    const std::string path = (std::filesystem::temp_directory_path() / "purl_test_world.png").string();
    // PNG stores 8-bit sRGB: write, then only compare estimators against each other.
    write_png(path, img);
    SceneDesc s;
    s.world.color = Vec3(1.0f);
    s.world.texture = path;
    s.world.rotation_z = 0.7f;
    const Lights lights(s);
    const Estimates e = estimate(lights);
    EXPECT_NEAR(e.pdf_integral, 1.0, 0.03);
    EXPECT_NEAR(e.irradiance_uniform / e.irradiance_light, 1.0, 0.03);
    std::filesystem::remove(path);
}
