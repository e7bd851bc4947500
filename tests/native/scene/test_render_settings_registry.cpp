// The render settings of base/registry.h against what the scene reader and RenderSettings do.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "base/input_error.h"
#include "base/registry.h"
#include "bsdf/bysdf_params.h"
#include "scene/scene_json.h"

using namespace purl;

namespace {

const char* kScene = R"({"camera": {"position": [0, -5, 1], "look_at": [0, 0, 0]},
    "meshes": [{"vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,2]]}])";

SceneDesc with_render(const std::string& render) {
    return parse_scene_text(std::string(kScene) + (render.empty() ? "" : ", \"render\": " + render) + "}", "s.json", "");
}

}  // namespace

TEST(RenderSettingsRegistry, DefaultsAreRenderSettingsDefaultsAndTheReaders) {
    const RenderSettings defaults;
    for (const RenderSettings& r : {defaults, with_render("").render}) {
        EXPECT_EQ(float(r.spp), render_setting("spp").default_value[0]);
        EXPECT_EQ(float(r.seed), render_setting("seed").default_value[0]);
        EXPECT_EQ(float(r.max_depth), render_setting("max_depth").default_value[0]);
        EXPECT_EQ(float(r.threads), render_setting("threads").default_value[0]);
        EXPECT_EQ(r.clamp, render_setting("clamp").default_value[0]);
        EXPECT_EQ(r.filter_glossy, render_setting("filter_glossy").default_value[0]);
        EXPECT_EQ(float(r.model), render_setting("model").default_value[0]);
        EXPECT_EQ(float(r.ply_method), render_setting("ply_method").default_value[0]);
        EXPECT_EQ(r.trace_only, std::string(integrators().default_name) == "trace");
    }
}

TEST(RenderSettingsRegistry, TheReaderTakesExactlyTheDeclaredRanges) {
    for (const char* name : {"spp", "seed", "max_depth", "threads"}) {
        const ParamInfo& s = render_setting(name);
        const long long lo = (long long)s.min_value, hi = (long long)s.max_value;
        EXPECT_NO_THROW(with_render("{\"" + std::string(name) + "\": " + std::to_string(lo) + "}")) << name;
        EXPECT_NO_THROW(with_render("{\"" + std::string(name) + "\": " + std::to_string(hi) + "}")) << name;
        EXPECT_THROW(with_render("{\"" + std::string(name) + "\": " + std::to_string(lo - 1) + "}"), InputError)
            << name;
        EXPECT_THROW(with_render("{\"" + std::string(name) + "\": " + std::to_string(hi + 1) + "}"), InputError)
            << name;
    }
    EXPECT_THROW(with_render(R"({"filter_glossy": 10.5})"), InputError);
    for (const Choice& c : ply_methods().choices)
        EXPECT_EQ(float(with_render(std::string(R"({"ply_method": ")") + c.name + "\"}").render.ply_method), c.value);
    EXPECT_TRUE(with_render(R"({"integrator": "trace"})").render.trace_only);
    EXPECT_THROW(with_render(R"({"model": "explicit"})"), InputError);
}

// The material table's eta range is the one the BYSDF clamps any other value to.
TEST(RenderSettingsRegistry, EtaRangeIsTheClamp) {
    const ParamInfo* eta = nullptr;
    for (const ParamInfo& p : bysdf_param_table())
        if (std::string(p.name) == "eta") eta = &p;
    ASSERT_NE(eta, nullptr);
    EXPECT_EQ(float(eta->min_value), kFiberEta.min);
    EXPECT_EQ(float(eta->max_value), kFiberEta.max);
}

// The registry's values are the enums' (YarnModel lives in scene/, PlyCrossSection in base/).
TEST(RenderSettingsRegistry, ChoiceValuesAreTheEnums) {
    EXPECT_EQ(parse_yarn_model("bysdf", "s"), YarnModel::Bysdf);
    EXPECT_EQ(parse_yarn_model("ply", "s"), YarnModel::Ply);
    EXPECT_EQ(parse_yarn_model("fiber", "s"), YarnModel::Fiber);
    EXPECT_EQ(parse_ply_method("local", "s"), PlyCrossSection::local);
    EXPECT_EQ(parse_multiscale_mode("far"), MultiscaleMode::Far);
    EXPECT_EQ(parse_multiscale_mode("auto"), MultiscaleMode::Auto);
    EXPECT_STREQ(multiscale_aggregation_name(MultiscaleAggregation::Aggregate), "aggregate");
}
