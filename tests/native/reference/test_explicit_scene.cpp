// make_explicit_scene: which sets it converts and how, the memory estimate against Embree's
// own count, the budget refusal, and the BCC + radii export.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "reference/explicit_export.h"
#include "reference/explicit_models.h"
#include "reference_fixture.h"
#include "scene/embree_scene.h"
#include "base/input_error.h"

namespace purl::test {
namespace {

SceneDesc two_set_scene() {
    SceneDesc s;
    s.source = "test.json";
    s.yarns.push_back(bysdf_set(wavy_yarn(0.1f), yarn_preset("prototype"), "wavy"));
    YarnSetDesc other;
    other.name = "placeholder";
    other.curves = straight_yarn(0.1f, 2.0f);
    other.material.model = MaterialModel::Placeholder;
    s.yarns.push_back(other);
    s.yarns.push_back(bysdf_set(loop_yarn(0.1f, 4), yarn_preset("B"), "loop"));
    s.yarns.back().material.fiber = fiber_bcsdf_preset("silk");
    MeshDesc m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    return s;
}

TEST(ExplicitScene, ConvertsBysdfSetsAndKeepsEverythingElse) {
    const SceneDesc scene = two_set_scene();
    const SceneDesc plies = make_explicit_scene(scene, YarnModel::Ply);
    ASSERT_EQ(plies.yarns.size(), 3u);
    EXPECT_EQ(plies.meshes.size(), 1u);
    EXPECT_EQ(plies.yarns[0].material.model, MaterialModel::Ply);
    EXPECT_EQ(plies.yarns[1].material.model, MaterialModel::Placeholder);
    EXPECT_EQ(plies.yarns[1].curves.point_count(), scene.yarns[1].curves.point_count());
    EXPECT_EQ(plies.yarns[2].material.model, MaterialModel::Ply);
    EXPECT_EQ(plies.yarns[0].curves.curve_count(), 3u);
    EXPECT_EQ(plies.yarns[2].curves.curve_count(), 3u);  // Zhao's B has 3 plies
    const PlyOrigins& o = plies.yarns[2].material.ply;
    ASSERT_TRUE(o.yarns);
    EXPECT_EQ(o.yarns->point_count(), scene.yarns[2].curves.point_count());
    EXPECT_EQ(o.curves.size(), 3u);
    // Curve keys continue across sets, as the BYSDF's shader counts them.
    EXPECT_EQ(o.key_base, uint32_t(scene.yarns[0].curves.curve_count() + scene.yarns[1].curves.curve_count()));
    EXPECT_TRUE(plies.yarns[2].curves.closed[0]);

    const SceneDesc fibers = make_explicit_scene(scene, YarnModel::Fiber);
    EXPECT_EQ(fibers.yarns[0].material.model, MaterialModel::Fiber);
    EXPECT_EQ(fibers.yarns[0].curves.curve_count(), size_t(3 * 25));
    EXPECT_EQ(fibers.yarns[2].curves.curve_count(), size_t(3 * 75));
    EXPECT_EQ(fibers.yarns[2].material.fiber.reflection_width, fiber_bcsdf_preset("silk").reflection_width);
    EXPECT_NO_THROW(validate_curves(fibers.yarns[2].curves, "fibers"));
    EXPECT_NO_THROW(validate_curves(plies.yarns[0].curves, "plies"));
    // The size computed beforehand is what was built.
    const ExplicitSize size = explicit_size(scene, YarnModel::Fiber);
    EXPECT_EQ(size.sets[1].curves, 0u);
    EXPECT_EQ(size.sets[2].curves, fibers.yarns[2].curves.curve_count());
    EXPECT_EQ(size.sets[2].control_points, fibers.yarns[2].curves.point_count());
    EXPECT_EQ(size.sets[0].segments, fibers.yarns[0].curves.segment_count());
}

TEST(ExplicitScene, MemoryEstimateMatchesEmbreesOwnCount) {
    // The estimate's Embree share (kEmbreeBytesPerSegment) against the device's memory monitor.
    GTEST_SKIP_WITHOUT_SHARED_DATA("glove.bcc");
    SceneDesc scene;
    scene.yarns.push_back(bysdf_set(glove_yarns(2), yarn_preset("prototype"), "glove"));
    scene.yarns[0].material.yarn.fiber_count = 8;
    for (YarnModel model : {YarnModel::Ply, YarnModel::Fiber}) {
        const SceneDesc e = make_explicit_scene(scene, model);
        const EmbreeScene embree(e);
        const double per_segment = double(embree.acceleration_bytes()) / double(e.yarns[0].curves.segment_count());
        std::printf(" %s: %zu segments, Embree %.1f bytes per segment (estimate uses %zu)\n",
                    model == YarnModel::Ply ? "plies" : "fibers", e.yarns[0].curves.segment_count(), per_segment,
                    kEmbreeBytesPerSegment);
        EXPECT_NEAR(per_segment, double(kEmbreeBytesPerSegment), 0.25 * kEmbreeBytesPerSegment);
    }
}

TEST(ExplicitScene, RefusesGeometryBeyondTheBudgetBeforeBuildingIt) {
    const SceneDesc scene = two_set_scene();
    ExplicitOptions tight;
    tight.memory_budget_bytes = 1e5;
    const ExplicitSize size = explicit_size(scene, YarnModel::Fiber, tight);
    ASSERT_GT(double(size.total.bytes), tight.memory_budget_bytes);
    try {
        make_explicit_scene(scene, YarnModel::Fiber, tight);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "test.json");
        EXPECT_EQ(e.place(), "render.model");
        EXPECT_NE(e.reason().find("budget"), std::string::npos) << e.reason();
        EXPECT_NE(e.reason().find("yarns[2] (loop)"), std::string::npos) << e.reason();  // the larger set
    }
    EXPECT_NO_THROW(make_explicit_scene(scene, YarnModel::Ply, tight));  // plies are small enough
    // The default budget (8 GiB) refuses a fiber glove with far too many fibers per ply.
    SceneDesc glove;
    GTEST_SKIP_WITHOUT_SHARED_DATA("glove.bcc");  // after the small scenes, which ran
    glove.yarns.push_back(bysdf_set(load_bcc(shared_data_path("glove.bcc"), 0.1f),
                                    yarn_preset("prototype"), "glove"));
    glove.yarns[0].material.yarn.fiber_count = 2000;
    EXPECT_THROW(make_explicit_scene(glove, YarnModel::Fiber), InputError);
}

TEST(ExplicitExport, BccAndRadiiDescribeTheSameCurves) {
    const SceneDesc e = make_explicit_scene(two_set_scene(), YarnModel::Ply);
    const std::string dir = (std::filesystem::temp_directory_path() / "purl_explicit_export").string();
    std::filesystem::create_directories(dir);
    const ExplicitExport written = write_explicit_curves(e, dir + "/plies.bcc", dir + "/plies.radii");
    std::vector<uint32_t> set_of_curve;
    const YarnCurves all = gather_explicit_curves(e, &set_of_curve);
    EXPECT_EQ(written.curves, 6u);
    EXPECT_EQ(set_of_curve, (std::vector<uint32_t>{0, 0, 0, 2, 2, 2}));
    const BccCurves bcc = read_bcc(dir + "/plies.bcc");
    EXPECT_EQ(bcc.header.type, "BS");
    EXPECT_EQ(bcc.curve_count(), 6u);
    ASSERT_EQ(bcc.points.size(), written.points);
    EXPECT_EQ(std::filesystem::file_size(dir + "/plies.radii"), written.points * sizeof(float));
    std::ifstream in(dir + "/plies.radii", std::ios::binary);
    std::vector<float> radii(written.points);
    in.read(reinterpret_cast<char*>(radii.data()), std::streamsize(radii.size() * sizeof(float)));
    // Loaded back with those radii, the file is the same curves, point for point.
    size_t k = 0;
    for (size_t c = 0; c < all.curve_count(); ++c) {
        const size_t n = bcc.curve_offsets[c + 1] - bcc.curve_offsets[c];
        EXPECT_EQ(bool(bcc.closed[c]), bool(all.closed[c]));
        for (size_t i = 0; i < n; ++i, ++k) {
            const Vec4& p = all.control_points[all.curve_offsets[c] + i];
            EXPECT_EQ(bcc.points[k].x, p.x);
            EXPECT_EQ(bcc.points[k].z, p.z);
            EXPECT_EQ(radii[k], p.w);
        }
    }
    EXPECT_EQ(k, written.points);
    EXPECT_THROW(write_explicit_curves(two_set_scene(), dir + "/none.bcc", dir + "/none.radii"), InputError);
}

}  // namespace
}  // namespace purl::test
