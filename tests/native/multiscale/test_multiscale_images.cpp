// The multi-scale BYSDF inside the renderer: the glove (BYSDF material) at three camera
// distances - close (a yarn spans ~13 pixels), mid (~3 pixels) and far (< 1 pixel) - in each
// mode, against small stored EXRs (tests/data/multiscale/*.exr) by relative RMSE of 16 x 16
// block means, like ExplicitImages. The test renders with another seed than the reference, so
// the metric sees Monte Carlo noise plus any change; tolerances sit above the seed-to-seed noise.
// Also: the renderer-level limits (footprint -> 0 gives near, footprint over the whole yarn
// gives far), the modes' agreement in the mean where they should agree, and the stats.
//
// Regenerate the references (after an intended change of appearance):
//   PURL_UPDATE_MULTISCALE_REFERENCES=1 ./test_multiscale --gtest_filter='MultiscaleImages.*'
// which also prints the seed-to-seed noise of every shot.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "base/input_error.h"
#include "io/image_io.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "support/reference_images.h"
#include "support/shared_data.h"

namespace purl {
namespace {

const std::string kDir = std::string(PURL_SOURCE_DIR) + "/tests/data/multiscale/";
constexpr uint64_t kReferenceSeed = 1, kTestSeed = 2;
constexpr int kBlock = 16;  // 64 x 80 film -> 4 x 5 blocks

bool updating() { return std::getenv("PURL_UPDATE_MULTISCALE_REFERENCES") != nullptr; }

struct Rendered {
    ImageRGB rgb;
    RenderStats stats;
};

Rendered render_mode(const Renderer& renderer, MultiscaleMode mode, uint64_t seed, float footprint_scale = 1.0f,
                     float max_h_samples = 0) {
    RenderSettings settings = renderer.scene().render;
    settings.multiscale.mode = mode;
    settings.multiscale.footprint_scale = footprint_scale;
    if (max_h_samples > 0) settings.multiscale.max_h_samples = max_h_samples;
    settings.seed = seed;
    settings.threads = 2;
    RenderControl control;
    const RenderResult r = renderer.render(settings, control);
    Rendered out;
    out.stats = r.stats;
    out.rgb = combined_rgb(r);
    return out;
}

double relative_rmse(const ImageRGB& a, const ImageRGB& b) { return block_relative_rmse(a, b, kBlock); }

double image_mean(const ImageRGB& a) {
    double sum = 0;
    for (float v : a.rgb) sum += v;
    return sum / double(std::max<size_t>(1, a.rgb.size()));
}

// Largest |a - b| over all pixels and channels, relative to the image mean of b.
double max_pixel_difference(const ImageRGB& a, const ImageRGB& b) {
    double worst = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) worst = std::max(worst, double(std::fabs(a.rgb[i] - b.rgb[i])));
    return worst / std::max(image_mean(b), 1e-12);
}

struct View {
    const char* name;
    double tolerance;  // 2.5 x the largest seed-to-seed noise of its four shots
};
// Measured seed-to-seed (seed 1 vs 2): close 0.084-0.111, mid 0.056-0.090, far 0.028-0.054.
const View kViews[] = {{"close", 0.28}, {"mid", 0.22}, {"far", 0.14}};
const MultiscaleMode kModes[] = {MultiscaleMode::Near, MultiscaleMode::Multi, MultiscaleMode::Far,
                                 MultiscaleMode::Auto};

std::string reference_name(const View& v, MultiscaleMode m) {
    return std::string("glove_") + v.name + "_" + multiscale_mode_name(m) + ".exr";
}

TEST(MultiscaleImages, GloveAtThreeDistancesMatchesItsReferences) {
    GTEST_SKIP_WITHOUT_SHARED_DATA("glove.bcc");  // the scenes name ../shared/data/glove.bcc
    for (const View& view : kViews) {
        const Renderer renderer(load_scene_file(kDir + "glove_" + view.name + ".json"));
        double near_mean = 0;
        for (MultiscaleMode mode : kModes) {
            const std::string name = reference_name(view, mode);
            const Rendered image = render_mode(renderer, mode, kTestSeed);
            const RenderStats& s = image.stats;
            const uint64_t hits = s.hits_near + s.hits_multi + s.hits_far;
            std::printf(" %-24s hits near %6llu multi %6llu far %6llu, mean h samples %5.2f, mean %.4f, %.1f s\n",
                        name.c_str(), (unsigned long long)s.hits_near, (unsigned long long)s.hits_multi,
                        (unsigned long long)s.hits_far, s.mean_h_samples(), image_mean(image.rgb), s.render_seconds);
            // Every camera hit on the yarn is counted once, by the mode that shaded it.
            EXPECT_GT(hits, 0u) << name;
            if (mode == MultiscaleMode::Near) {
                EXPECT_EQ(hits, s.hits_near) << name;
                EXPECT_DOUBLE_EQ(s.mean_h_samples(), 1.0) << name;
                near_mean = image_mean(image.rgb);
            }
            if (mode == MultiscaleMode::Multi) {
                EXPECT_EQ(hits, s.hits_multi) << name;
            }
            if (mode == MultiscaleMode::Far) {
                EXPECT_EQ(hits, s.hits_far) << name;
                // Forcing far on yarns wider than a pixel warns, once. (The far view has such
                // yarns too, where the glove comes closer, so it may warn as well.)
                if (std::string(view.name) != "far") {
                    EXPECT_EQ(s.warnings.size(), 1u) << name;
                }
                EXPECT_LE(s.warnings.size(), 1u) << name;
            } else {
                EXPECT_TRUE(s.warnings.empty()) << name;
            }
            if (mode == MultiscaleMode::Multi) {
                EXPECT_GT(s.mean_h_samples(), 1.0) << name;
            }
            if (mode == MultiscaleMode::Far) {
                EXPECT_EQ(s.h_samples, 0u) << name;  // the tabulated far field traces nothing
            }
            if (std::string(view.name) == "far" && mode != MultiscaleMode::Near) {
                // Yarns below a pixel: multi, far and auto average the pixel's yarn and
                // converge to the near field's mean. Measured with the traced ply crossing:
                // multi within 0.5 %, far and auto 0.975 (the table sits below the sampled far
                // field in back light, an open item in docs/multiscale.md), held at 3 %.
                EXPECT_NEAR(image_mean(image.rgb) / near_mean, 1.0, 0.03) << name;
            }
            if (updating()) {
                const Rendered reference = render_mode(renderer, mode, kReferenceSeed);
                write_rgb_exr(kDir + name, reference.rgb);
                std::printf(" %-24s seed-to-seed relative RMSE %.4f (tolerance %.3f)\n", name.c_str(),
                            relative_rmse(image.rgb, reference.rgb), view.tolerance);
                continue;
            }
            const double e = relative_rmse(image.rgb, read_image_rgb(kDir + name));
            std::printf(" %-24s relative RMSE %.4f (tolerance %.3f)\n", name.c_str(), e, view.tolerance);
            EXPECT_LE(e, view.tolerance) << name;
        }
    }
}

TEST(MultiscaleImages, FootprintLimitsGiveNearAndFar) {
    GTEST_SKIP_WITHOUT_SHARED_DATA("glove.bcc");
    // Multi with a footprint of 0 pixels is the near field: same random numbers, so equal up to
    // the transmission chord (the model attenuates along a straight local tube) and the paths
    // that then part at Russian roulette; with a footprint of 16 pixels at the mid view (a yarn ~3 pixels wide)
    // every footprint reaches both silhouettes, and multi is the far model exactly.
    const Renderer renderer(load_scene_file(kDir + "glove_mid.json"));
    const Rendered near = render_mode(renderer, MultiscaleMode::Near, kTestSeed);
    const Rendered zero = render_mode(renderer, MultiscaleMode::Multi, kTestSeed, 0.0f);
    const double d_near = relative_rmse(zero.rgb, near.rgb);
    std::printf(" multi, footprint 0 vs near: relative RMSE %.2e, largest pixel difference %.2e of the mean\n",
                d_near, max_pixel_difference(zero.rgb, near.rgb));
    EXPECT_LT(d_near, 0.03);  // measured 0.008; two seeds differ by 0.09
    EXPECT_EQ(zero.stats.hits_multi + zero.stats.hits_far, 0u);  // no footprint: shaded and counted near
    EXPECT_DOUBLE_EQ(zero.stats.mean_h_samples(), 1.0);

    // Multi over the whole yarn is the sampled far field; far mode shades the table built from
    // it (straight yarn, phase-averaged): equal within the noise of two models' paths.
    const Rendered wide = render_mode(renderer, MultiscaleMode::Multi, kTestSeed, 16.0f);
    const Rendered far = render_mode(renderer, MultiscaleMode::Far, kTestSeed, 16.0f);
    EXPECT_EQ(wide.stats.hits_far + wide.stats.hits_near, 0u);
    const double d_far = relative_rmse(wide.rgb, far.rgb), mean_ratio = image_mean(far.rgb) / image_mean(wide.rgb);
    std::printf(" multi, footprint 16 px vs far (table): relative RMSE %.3f, mean ratio %.4f\n", d_far, mean_ratio);
    EXPECT_LT(d_far, 0.22);  // the mid view's tolerance against its own references
    // Measured 0.970: the table is darker (docs/multiscale.md); 0.974 before bounce hits with
    // wide ray cones took the circular ply cut, which shifts the two models' bounces unequally.
    EXPECT_NEAR(mean_ratio, 1.0, 0.035);
    EXPECT_GT(max_pixel_difference(near.rgb, far.rgb), 0.1);  // and far is not near here
}

TEST(MultiscaleImages, SceneSettingsAreReadAndCheckedStrictly) {
    // A scene with one generated yarn and the given render.multiscale value.
    const auto with = [](const std::string& multiscale) {
        return R"({"version": 1, "camera": {"position": [0, -5, 0], "look_at": [0, 0, 0]},
                   "yarns": [{"generate": {"kind": "plain"}}], "render": {"multiscale": )" +
               multiscale + "}}";
    };
    const SceneDesc s = parse_scene_text(with(R"({"mode": "far", "aggregation": "aggregate",
        "multiscale_max_h_samples": 9, "multiscale_footprint_scale": 2})"),
                                         "ms.json", "", nullptr);
    EXPECT_EQ(s.render.multiscale.mode, MultiscaleMode::Far);
    EXPECT_EQ(s.render.multiscale.aggregation, MultiscaleAggregation::Aggregate);
    EXPECT_EQ(s.render.multiscale.max_h_samples, 9.0f);
    EXPECT_EQ(s.render.multiscale.footprint_scale, 2.0f);
    EXPECT_EQ(s.render.multiscale.roughness_c, default_multiscale_settings().roughness_c);
    const SceneDesc d = parse_scene_text(with("{}"), "ms.json", "", nullptr);
    EXPECT_EQ(d.render.multiscale.mode, MultiscaleMode::Auto);

    const char* bad[] = {
        R"({"mode": "closeup"})",                  // unknown mode
        R"({"modes": "auto"})",                    // unknown key
        R"({"multiscale_max_h_samples": 2.5})",    // not a whole number
        R"({"multiscale_footprint_scale": -1})",   // out of range
        R"("auto")",                               // not an object
    };
    for (const char* b : bad) {
        try {
            parse_scene_text(with(b), "ms.json", "", nullptr);
            ADD_FAILURE() << "accepted " << b;
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("ms.json"), std::string::npos) << what;
            EXPECT_NE(what.find("multiscale"), std::string::npos) << what;
        }
    }
}

}  // namespace
}  // namespace purl
