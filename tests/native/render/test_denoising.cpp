// The denoiser's guide passes, Open Image Denoise loaded at run time, and path regularisation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "render/denoise.h"
#include "render/denoising_features.h"
#include "render/film.h"
#include "render/path_regularization.h"
#include "render/renderer.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

// A (0.25, 0.5, 0.75) diffuse quad facing a camera on -y, filling the middle of the film.
SceneDesc quad_scene(const std::string& render_extra = "") {
    const std::string text = R"({
        "camera": {"position": [0, -3, 0], "look_at": [0, 0, 0], "lens": 50},
        "film": {"width": 48, "height": 32},
        "render": {"spp": 4, "seed": 1, "max_depth": 4, "threads": 2)" + render_extra + R"(},
        "world": {"color": [0.2, 0.2, 0.2]},
        "lights": [{"type": "area", "size": 1, "position": [0.5, -2, 1], "look_at": [0, 0, 0], "power": 100}],
        "meshes": [{"name": "quad", "color": [0.25, 0.5, 0.75],
                    "vertices": [[-0.5, 0, -0.4], [0.5, 0, -0.4], [0.5, 0, 0.4], [-0.5, 0, 0.4]],
                    "triangles": [[0, 1, 2], [0, 2, 3]]}]
    })";
    return parse_scene_text(text, "quad.json", "");
}

const float* pixel(const RenderImage& image, const char* pass, int x, int y) {
    const ImagePass* p = image.find(pass);
    EXPECT_NE(p, nullptr) << pass;
    return &p->pixels[(size_t(y) * image.width + x) * p->channels()];
}

TEST(DenoisingFeatures, DiffuseSurfaceGivesItsAlbedoAndCameraFacingNormal) {
    const Renderer renderer(quad_scene());
    RenderControl control;
    const RenderImage image = renderer.render(control).image;
    const float* albedo = pixel(image, kDenoisingAlbedoPass, 24, 16);
    EXPECT_NEAR(albedo[0], 0.25f, 1e-5f);
    EXPECT_NEAR(albedo[1], 0.5f, 1e-5f);
    EXPECT_NEAR(albedo[2], 0.75f, 1e-5f);
    // Camera space: the quad faces the camera, +z toward the viewer.
    const float* normal = pixel(image, kDenoisingNormalPass, 24, 16);
    EXPECT_NEAR(normal[0], 0.0f, 1e-4f);
    EXPECT_NEAR(normal[1], 0.0f, 1e-4f);
    EXPECT_NEAR(normal[2], 1.0f, 1e-4f);
    // The corner sees the world only: no surface, no features.
    EXPECT_EQ(pixel(image, kDenoisingAlbedoPass, 0, 0)[1], 0.0f);
    EXPECT_EQ(pixel(image, kDenoisingNormalPass, 0, 0)[2], 0.0f);
}

TEST(DenoisingFeatures, BysdfAlbedoSumsItsLobesAndStaysBelowOne) {
    BysdfParams p = default_bysdf_params();
    p.body_reflection_albedo = Vec3(0.8f, 0.1f, 0.1f);
    p.body_transmission_albedo = Vec3(0.8f, 0.1f, 0.1f);
    p.sigma_t_specular = p.sigma_t_body = 0;  // nothing lost on the way through
    const Bysdf bsdf(p, BysdfShadingPoint{});
    ShadingPoint sp;
    sp.bsdf = bsdf;
    for (float cos_o : {0.05f, 0.5f, 1.0f}) {
        const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);
        const DenoisingAlbedo a = denoising_albedo(sp, wo);
        Vec3 lobes[4];
        bsdf.lobe_albedos(wo, lobes);
        const Vec3 sum = lobes[0] + lobes[1] + lobes[2] + lobes[3];
        EXPECT_NEAR(a.total.x, std::min(sum.x, 1.0f), 1e-5f);
        EXPECT_GT(a.total.x, a.total.y);  // the red body shows
        EXPECT_LE(a.total.x, 1.0f);
        EXPECT_EQ(a.sharp.x, 0.0f);  // alpha 0.2 and more: nothing is a mirror
    }
}

TEST(DenoisingFeatures, MirrorLikeLobesPassTheFeaturesOn) {
    BysdfParams p = default_bysdf_params();
    p.body_share = 0;  // specular only
    p.specular_roughness_along = p.specular_roughness_across = p.transmission_roughness = 0.01f;
    ShadingPoint sp;
    sp.bsdf = Bysdf(p, BysdfShadingPoint{});
    EXPECT_GT(average(denoising_albedo(sp, Vec3(0, 0, 1)).sharp), 0.9f * average(denoising_albedo(sp, Vec3(0, 0, 1)).total));
    const Camera camera(CameraDesc{}, FilmDesc{});
    DenoisingPath path;
    path.record(sp, Vec3(0, 0, 1), camera);
    EXPECT_FALSE(path.done());  // looks through the mirror
    ShadingPoint diffuse;
    diffuse.bsdf = DiffuseBsdf{Vec3(0.5f)};
    path.record(diffuse, Vec3(0, 0, 1), camera);
    EXPECT_TRUE(path.done());
    EXPECT_LT(path.albedo().x, 0.5f);  // tinted by what the mirror reflects
    EXPECT_GT(path.albedo().x, 0.0f);
}

TEST(PathRegularization, CyclesRule) {
    EXPECT_EQ(regularization_alpha(0.0f, 0.1f), 0.0f);        // off
    EXPECT_EQ(regularization_alpha(1.0f, 5.0f), 0.0f);        // after a glossy bounce: nothing
    EXPECT_NEAR(regularization_alpha(1.0f, 0.0f), 0.5f, 1e-6f);
    EXPECT_NEAR(regularization_alpha(1.0f, 0.36f), 0.4f, 1e-6f);
    EXPECT_EQ(regularization_alpha(1.0f, std::numeric_limits<float>::infinity()), 0.0f);  // no bounce yet
}

TEST(PathRegularization, RougheningWidensTheHighlightAndKeepsItsEnergy) {
    BysdfParams p = default_bysdf_params();
    p.body_share = 0;
    ShadingPoint sp;
    sp.bsdf = Bysdf(p, BysdfShadingPoint{});
    const Vec3 wo = normalize(Vec3(0.3f, 0.1f, 1.0f)), mirror(-wo.x, -wo.y, wo.z);
    const float peak = max_component(sp.eval_pdf(wo, mirror, ShadingPoint::Exit{}).f);
    Vec3 lobes_before[4], lobes_after[4];
    sp.bsdf.get_if<Bysdf>()->lobe_albedos(wo, lobes_before);
    roughen(sp, 0.5f);
    EXPECT_LT(max_component(sp.eval_pdf(wo, mirror, ShadingPoint::Exit{}).f), 0.5f * peak);
    sp.bsdf.get_if<Bysdf>()->lobe_albedos(wo, lobes_after);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(lobes_before[i].x, lobes_after[i].x);
}

TEST(PathRegularization, DiffuseSceneIsUnchanged) {
    RenderControl control;
    const RenderImage off = Renderer(quad_scene(R"(, "filter_glossy": 0)")).render(control).image;
    const RenderImage on = Renderer(quad_scene()).render(control).image;
    // A diffuse quad has no glossy lobe to roughen: identical images.
    EXPECT_EQ(off.find("Combined")->pixels, on.find("Combined")->pixels);
}

TEST(Denoise, MissingLibraryIsAClearErrorNotACrash) {
    try {
        Denoiser::load_from({"/nonexistent/libOpenImageDenoise.so.2"});
        FAIL() << "expected DenoiserUnavailable";
    } catch (const DenoiserUnavailable& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("pip install pyoidn"), std::string::npos) << message;
        EXPECT_NE(message.find("/nonexistent/libOpenImageDenoise.so.2"), std::string::npos) << message;
    }
    // A library that is not OIDN: found, but refused by name.
    EXPECT_THROW(Denoiser::load_from({"libm.so.6"}), DenoiserUnavailable);
}

TEST(Denoise, RemovesNoiseAndKeepsTheInput) {
    std::shared_ptr<const Denoiser> denoiser;
    try {
        denoiser = Denoiser::load();
    } catch (const DenoiserUnavailable& e) {
        GTEST_SKIP() << e.what();  // scripts/setup.sh installs pyoidn; CI has it
    }
    SceneDesc scene = quad_scene();
    RenderControl control;
    RenderImage image = Renderer(scene).render(control).image;
    scene.render.spp = 256;
    const RenderImage converged = Renderer(scene).render(control).image;
    const std::vector<float> noisy = image.find("Combined")->pixels;
    denoiser->denoise(image, {});
    ASSERT_NE(image.find(kNoisyImagePass), nullptr);
    EXPECT_EQ(image.find(kNoisyImagePass)->pixels, noisy);
    const std::vector<float>& clean = image.find("Combined")->pixels;
    const std::vector<float>& truth = converged.find("Combined")->pixels;
    double error_noisy = 0, error_clean = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
        if (i % 4 == 3) {
            EXPECT_EQ(clean[i], noisy[i]);  // alpha kept
            continue;
        }
        error_noisy += (noisy[i] - truth[i]) * (noisy[i] - truth[i]);
        error_clean += (clean[i] - truth[i]) * (clean[i] - truth[i]);
    }
    EXPECT_LT(error_clean, 0.5 * error_noisy);
}

}  // namespace
}  // namespace purl
