// The scattering interface evaluates the BYSDF once per light sample and once per BSDF sample
// (render/scattering.h): next-event estimation takes f and the MIS pdf from one eval_pdf, and a
// sample asks for its exit before it evaluates, so its f needs no second evaluation for the
// chord. Before, a light sample that reached the light evaluated twice (f, then the pdf) and a
// transmitted or ply-crossing sample twice (the sample, then f along its exit).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene_json.h"

namespace purl {
namespace {

// A straight three-ply BYSDF yarn under a grey sky, shaded near (one BYSDF per hit).
SceneDesc straight_yarn_scene(int ply_crossing) {
    const std::string text = R"({
        "camera": {"position": [0, -1.2, 0], "look_at": [0, 0, 0], "lens": 50},
        "film": {"width": 48, "height": 24},
        "render": {"spp": 4, "seed": 3, "max_depth": 6, "threads": 2, "multiscale": {"mode": "near"}},
        "world": {"color": [0.5, 0.5, 0.5]},
        "yarns": [{"arrays": "yarn", "material": {"model": "bysdf", "ply_crossing": )" +
                             std::to_string(ply_crossing) + R"(, "yarn": {"preset": "prototype"}}}]})";
    ExternalArrays arrays;
    arrays.yarns = [](const std::string&) {
        YarnCurves c;
        std::vector<Vec4> p;
        for (int i = 0; i < 12; ++i) p.emplace_back(-0.55f + 0.1f * i, 0.0f, 0.0f, 0.1f);
        c.add_curve(p.data(), p.size(), false);
        return c;
    };
    return parse_scene_text(text, "scatter_evaluations.json", "", &arrays);
}

TEST(ScatterEvaluations, OnePerLightSampleAndOnePerBsdfSample) {
    for (int crossing : {0, 1}) {
        SCOPED_TRACE(crossing ? "traced ply crossing" : "paper's ply crossing");
        const Renderer renderer(straight_yarn_scene(crossing));
        RenderControl control;
        const RenderStats s = renderer.render(control).stats;
        // Every interaction is a BYSDF hit here: at most one light sample and one BSDF sample.
        const double interactions = s.mean_path_length * double(s.samples);
        ASSERT_GT(interactions, 100.0);
        EXPECT_LE(double(s.bysdf_evaluations), 2 * interactions + 0.5);
        // Both are counted (the sky is always sampled; few samples fail).
        EXPECT_GT(double(s.bysdf_evaluations), 1.5 * interactions);
        std::printf("ply_crossing %d: %.0f interactions, %llu BYSDF evaluations (%.3f per interaction)\n", crossing,
                    interactions, (unsigned long long)s.bysdf_evaluations, double(s.bysdf_evaluations) / interactions);
    }
}

}  // namespace
}  // namespace purl
