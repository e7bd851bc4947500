// The PlyIndex and PlyUV passes: a straight three-ply BYSDF yarn along x seen from -y. Every
// ply shows, v_ply follows the yarn's arc length along the image (it is measured along the
// ply: yarn length times the helix's stretch), and pixels without a yarn carry -1 and (0, 0).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "render/shading.h"
#include "scene/embree_scene.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

constexpr float kRadius = 0.1f;

// `camera_x` moves the camera along the yarn (it still looks at the origin); `ply_method` is
// render.ply_method.
SceneDesc straight_yarn_scene(float camera_x = 0, const std::string& ply_method = "elliptical") {
    const std::string text = R"({
        "camera": {"position": [)" + std::to_string(camera_x) + R"(, -1.2, 0], "look_at": [0, 0, 0], "lens": 50},
        "film": {"width": 48, "height": 24},
        "render": {"spp": 1, "seed": 5, "max_depth": 2, "threads": 2, "ply_method": ")" + ply_method + R"("},
        "world": {"color": [0.2, 0.2, 0.2]},
        "yarns": [{"arrays": "yarn", "material": {"model": "bysdf", "yarn": {"preset": "prototype"}}}]})";
    ExternalArrays arrays;
    arrays.yarns = [](const std::string&) {
        YarnCurves c;
        std::vector<Vec4> p;
        for (int i = 0; i < 12; ++i) p.emplace_back(-0.55f + 0.1f * i, 0.0f, 0.0f, kRadius);
        c.add_curve(p.data(), p.size(), false);
        return c;
    };
    return parse_scene_text(text, "ply_passes.json", "", &arrays);
}

TEST(PlyPasses, IndexAndCoordinatesOfTheFirstPlyHit) {
    const SceneDesc scene = straight_yarn_scene();
    const YarnDescription& d = scene.yarns[0].material.yarn;
    const Renderer renderer(scene);
    RenderControl control;
    const RenderResult r = renderer.render(control);
    const ImagePass* index = r.image.find("PlyIndex");
    const ImagePass* uv = r.image.find("PlyUV");
    const ImagePass* id = r.image.find("YarnID");
    ASSERT_TRUE(index && uv && id);
    ASSERT_EQ(index->channels(), 1);
    ASSERT_EQ(uv->channels(), 2);

    const float rate = d.ply_handedness * d.ply_twist / kRadius;
    const float stretch = std::sqrt(1 + std::pow(d.ply_distance * kRadius * rate, 2.0f));
    std::set<int> plies;
    int hits = 0;
    double sx = 0, sv = 0, sxx = 0, sxv = 0;
    for (int y = 0; y < r.image.height; ++y)
        for (int x = 0; x < r.image.width; ++x) {
            const size_t i = size_t(y) * r.image.width + x;
            const float ply = index->pixels[i], u = uv->pixels[2 * i], v = uv->pixels[2 * i + 1];
            EXPECT_EQ(ply, std::round(ply));
            if (id->pixels[i] == 0) {  // background: no ply
                EXPECT_EQ(ply, -1.0f);
                EXPECT_EQ(u, 0.0f);
                EXPECT_EQ(v, 0.0f);
                continue;
            }
            if (ply < 0) continue;  // between the plies
            EXPECT_LT(ply, float(d.plies()));
            EXPECT_GE(u, 0.0f);
            EXPECT_LT(u, 2 * kPi);
            plies.insert(int(ply));
            ++hits;
            sx += x, sv += v, sxx += double(x) * x, sxv += double(x) * v;
        }
    EXPECT_EQ(int(plies.size()), d.plies());
    ASSERT_GT(hits, 100);
    // v_ply along the image: the Catmull-Rom curve runs along +x from its second point, x =
    // -0.45 m, and one pixel is 1.2 m * 36 / 50 / 48 wide at the yarn.
    const double slope = (hits * sxv - sx * sv) / (hits * sxx - sx * sx);
    const double pixel = 1.2 * 36.0 / 50.0 / 48.0;
    EXPECT_NEAR(slope / (pixel * stretch), 1.0, 0.05);
    const double v_centre = (sv - slope * sx) / hits + slope * 23.5;  // at the image's centre column
    EXPECT_NEAR(v_centre / stretch, 0.45, 0.02);
}

// render.ply_method reaches the search: on a straight yarn seen at ~40 degrees the local method
// is exact, so it finds the same plies as the elliptical one, while the circular cross-section
// (the comparison method) puts part of the pixels on other plies.
TEST(PlyPasses, PlyMethodChoosesTheSearch) {
    const auto ply_indices = [](const std::string& method) {
        const Renderer renderer(straight_yarn_scene(1.0f, method));
        RenderControl control;
        const RenderResult r = renderer.render(control);
        const ImagePass* index = r.image.find("PlyIndex");
        return index ? index->pixels : std::vector<float>();
    };
    const std::vector<float> elliptical = ply_indices("elliptical"), local = ply_indices("local"),
                             circular = ply_indices("circular");
    ASSERT_FALSE(elliptical.empty());
    const auto agreement = [&](const std::vector<float>& other) {
        int both = 0, same = 0;
        for (size_t i = 0; i < elliptical.size(); ++i) {
            if (elliptical[i] < 0 || other[i] < 0) continue;
            ++both;
            same += other[i] == elliptical[i];
        }
        EXPECT_GT(both, 100);
        return double(same) / std::max(both, 1);
    };
    EXPECT_GE(agreement(local), 0.99);
    EXPECT_LT(agreement(circular), 0.95);
}

// A bounce ray (no multi-scale context) whose cone at the hit spans a ply radius or more finds
// its ply by the circular cross-section; a narrower one by the scene's method. Rays from the
// oblique camera of the test above, shaded as bounces.
TEST(PlyPasses, BounceConeChoosesTheSearch) {
    const SceneDesc exact_scene = straight_yarn_scene(1.0f, "elliptical");
    const SceneDesc circular_scene = straight_yarn_scene(1.0f, "circular");
    const EmbreeScene geometry(exact_scene);
    const SurfaceShader exact(exact_scene), circular(circular_scene);
    const YarnDescription& d = exact_scene.yarns[0].material.yarn;
    const float ply_radius_m = d.ply_radius * kRadius;  // the cone width where bounces turn circular
    const Vec3 eye(1.0f, -1.2f, 0.0f);
    int hits = 0, wide_as_circular = 0, narrow_as_exact = 0, circular_differs = 0;
    for (int i = 0; i < 40; ++i) {
        for (int j = 0; j < 8; ++j) {
            Ray ray;
            ray.origin = eye;
            ray.direction = normalize(Vec3(-0.45f + 0.02f * i, 0.0f, -0.09f + 0.025f * j) - eye);
            SurfaceHit hit;
            if (!geometry.intersect(ray, hit)) continue;
            ++hits;
            const SurfaceInteraction e = exact.shade(hit, ray, nullptr, 0.9f * ply_radius_m);
            const SurfaceInteraction w = exact.shade(hit, ray, nullptr, 1.1f * ply_radius_m);
            const SurfaceInteraction c = circular.shade(hit, ray, nullptr, 0.0f);
            const auto same = [](const SurfaceInteraction& a, const SurfaceInteraction& b) {
                return a.pass_through == b.pass_through && a.ply_index == b.ply_index &&
                       (a.pass_through || length(a.point.position - b.point.position) < 1e-6f);
            };
            wide_as_circular += same(w, c);
            narrow_as_exact += same(e, exact.shade(hit, ray, nullptr, 0.0f));
            circular_differs += !same(e, c);
        }
    }
    ASSERT_GT(hits, 100);
    EXPECT_EQ(wide_as_circular, hits);
    EXPECT_EQ(narrow_as_exact, hits);
    EXPECT_GT(circular_differs, hits / 20);  // the two searches do differ here, so the choice shows
}

}  // namespace
}  // namespace purl
