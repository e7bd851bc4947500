// Per-yarn colours end to end: two parallel yarns in one set, one given a red and one a blue
// curve colour, rendered small; the YarnID pass tells whose pixels are whose.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

// Two straight yarns along x, one above the other, in front of a camera on -y.
YarnCurves two_yarns() {
    YarnCurves c;
    for (int k = 0; k < 2; ++k) {
        std::vector<Vec4> p;
        for (int i = 0; i < 10; ++i) p.emplace_back(-0.9f + 0.2f * i, 0.0f, k == 0 ? 0.14f : -0.14f, 0.09f);
        c.add_curve(p.data(), p.size(), false);
    }
    return c;
}

SceneDesc two_yarn_scene(const std::string& material, const std::vector<Vec3>& colors) {
    const std::string text = R"({
        "camera": {"position": [0, -2, 0], "look_at": [0, 0, 0], "lens": 50},
        "film": {"width": 64, "height": 32},
        "render": {"spp": 4, "seed": 3, "max_depth": 4, "threads": 2},
        "world": {"color": [0.05, 0.05, 0.05]},
        "lights": [{"type": "area", "size": 0.5, "position": [0.3, -1.5, 0.8], "look_at": [0, 0, 0], "power": 40}],
        "yarns": [{"arrays": "two", "material": )" + material + "}]}";
    ExternalArrays arrays;
    arrays.yarns = [&](const std::string&) {
        YarnCurves c = two_yarns();
        c.colors = colors;
        return c;
    };
    return parse_scene_text(text, "two_yarns.json", "", &arrays);
}

struct YarnMeans {
    Vec3 rgb[2];
    int pixels[2] = {0, 0};
};

YarnMeans render_means(SceneDesc scene) {
    const Renderer renderer(std::move(scene));
    RenderControl control;
    const RenderResult r = renderer.render(control);
    const ImagePass* combined = r.image.find("Combined");
    const ImagePass* ids = r.image.find("YarnID");
    YarnMeans m;
    for (size_t i = 0; i < ids->pixels.size(); ++i) {
        const int yarn = int(ids->pixels[i]) - 1;  // curve id + 1; 0 is background
        if (yarn < 0 || yarn > 1) continue;
        const float* px = &combined->pixels[i * combined->channels()];
        m.rgb[yarn] += Vec3(px[0], px[1], px[2]);
        ++m.pixels[yarn];
    }
    for (int k = 0; k < 2; ++k) m.rgb[k] = m.rgb[k] * (1.0f / float(std::max(1, m.pixels[k])));
    return m;
}

const std::vector<Vec3> kRedAndBlue = {Vec3(1.0f, 0.1f, 0.1f), Vec3(0.1f, 0.1f, 1.0f)};

TEST(CurveColorsRender, EachBysdfYarnTakesItsOwnColour) {
    // An orange body with no blue at all: a blue yarn can only come from the override. (The
    // specular lobes stay white, so neither yarn is a pure colour.)
    const std::string orange =
        R"({"model": "bysdf", "body_reflection_albedo": [0.6, 0.3, 0], "body_transmission_albedo": [0.8, 0.4, 0]})";
    const YarnMeans plain = render_means(two_yarn_scene(orange, {}));
    const YarnMeans colored = render_means(two_yarn_scene(orange, kRedAndBlue));
    for (int k = 0; k < 2; ++k) {
        ASSERT_GT(plain.pixels[k], 40) << "yarn " << k << " should cover part of the image";
        ASSERT_GT(colored.pixels[k], 40);
    }
    // Without colours both yarns are the material's orange: red well above blue.
    EXPECT_GT(plain.rgb[1].x, 1.5f * plain.rgb[1].z) << plain.rgb[1].x << " " << plain.rgb[1].z;
    // With them, yarn 0 is red and yarn 1 blue.
    EXPECT_GT(colored.rgb[0].x, 2.0f * colored.rgb[0].z) << colored.rgb[0].x << " " << colored.rgb[0].z;
    EXPECT_GT(colored.rgb[1].z, 2.0f * colored.rgb[1].x) << colored.rgb[1].x << " " << colored.rgb[1].z;
}

TEST(CurveColorsRender, FarModeKeepsTheColours) {
    // Multi-scale shading of camera hits takes the same recoloured material (MultiscaleYarn::params).
    const std::string orange =
        R"({"model": "bysdf", "body_reflection_albedo": [0.6, 0.3, 0], "body_transmission_albedo": [0.8, 0.4, 0]})";
    SceneDesc scene = two_yarn_scene(orange, kRedAndBlue);
    scene.render.multiscale.mode = MultiscaleMode::Far;
    const YarnMeans m = render_means(std::move(scene));
    EXPECT_GT(m.rgb[0].x, 2.0f * m.rgb[0].z) << m.rgb[0].x << " " << m.rgb[0].z;
    EXPECT_GT(m.rgb[1].z, 2.0f * m.rgb[1].x) << m.rgb[1].x << " " << m.rgb[1].z;
}

TEST(CurveColorsRender, PlaceholderYarnsTakeTheirColourToo) {
    const std::string grey = R"({"model": "placeholder", "color": [0.7, 0.7, 0.7]})";
    const YarnMeans m = render_means(two_yarn_scene(grey, kRedAndBlue));
    EXPECT_GT(m.rgb[0].x, 2.0f * m.rgb[0].z);
    EXPECT_GT(m.rgb[1].z, 2.0f * m.rgb[1].x);
}

}  // namespace
}  // namespace purl
