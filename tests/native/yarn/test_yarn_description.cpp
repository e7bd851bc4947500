#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "base/input_error.h"
#include "yarn/yarn_description.h"

namespace purl {
namespace {

// Expects `body` to throw InputError whose place names `field`.
template <class F>
void expect_error_at(F body, const std::string& field) {
    try {
        body();
        FAIL() << "no InputError for " << field;
    } catch (const InputError& e) {
        EXPECT_NE(e.place().find(field), std::string::npos) << e.what();
    }
}

TEST(YarnDescription, TableDeclaresEveryFieldOnceWithItsDefault) {
    const auto& table = yarn_description_params();
    // Every float of the struct is declared, each at its own offset, with a unique name.
    EXPECT_EQ(table.size() * sizeof(float), sizeof(YarnDescription));
    std::set<size_t> offsets;
    std::set<std::string> names;
    for (const ParamInfo& p : table) {
        offsets.insert(p.offset);
        names.insert(p.name);
        EXPECT_LE(p.min_value, p.default_value[0]) << p.name;
        EXPECT_GE(p.max_value, p.default_value[0]) << p.name;
        EXPECT_GT(std::string(p.doc).size(), 10u) << p.name;
    }
    EXPECT_EQ(offsets.size(), table.size());
    EXPECT_EQ(names.size(), table.size());
    const YarnDescription d = default_yarn_description();
    EXPECT_EQ(d.plies(), 3);
    EXPECT_NEAR(d.ply_radius, 0.45f, 1e-6f);
    EXPECT_NEAR(d.ply_distance, 0.45f / std::sin(3.14159265f / 3), 1e-5f);
    EXPECT_NO_THROW(check_yarn_description(d, "f.json", "yarn"));
}

TEST(YarnDescription, ZhaoSetsConvertToRelativeUnits) {
    const auto names = yarn_preset_names();
    EXPECT_EQ(names.size(), 10u);
    for (const std::string& n : names) EXPECT_NO_THROW(check_yarn_description(yarn_preset(n), "", n)) << n;
    // Set A: ply centres at 0.0507 / 2, ply radius sqrt(0.0531 * 0.0356), pitch 0.639.
    const YarnDescription a = yarn_preset("A");
    const float centre = 0.02535f, ply = std::sqrt(0.0531f * 0.0356f), yarn = centre + ply;
    EXPECT_EQ(a.plies(), 2);
    EXPECT_EQ(a.fibers(), 150);
    EXPECT_NEAR(a.ply_distance, centre / yarn, 1e-5f);
    EXPECT_NEAR(a.ply_radius, ply / yarn, 1e-5f);
    EXPECT_NEAR(a.ply_distance + a.ply_radius, 1.0f, 1e-6f);
    EXPECT_NEAR(a.ply_twist, 2 * 3.14159265f * yarn / 0.639f, 1e-4f);
    EXPECT_NEAR(a.fiber_twist, 2 * 3.14159265f * yarn / 0.710f, 1e-4f);
    EXPECT_NEAR(a.migration_rho_min, 0.85f, 1e-6f);
    EXPECT_NEAR(a.migration_frequency, 1.9f, 1e-6f);
    EXPECT_NEAR(a.density_eps, 0.139f, 1e-6f);
    EXPECT_EQ(yarn_preset("H").plies(), 3);
    expect_error_at([] { yarn_preset("Z"); }, "Z");
}

TEST(YarnDescription, ValidationNamesTheFieldAndReason) {
    const YarnDescription ok = default_yarn_description();
    auto check = [](YarnDescription d) { check_yarn_description(d, "scene.json", "yarns[0].structure"); };
    YarnDescription d = ok;
    d.ply_count = 13;
    expect_error_at([&] { check(d); }, "ply_count");
    d = ok;
    d.ply_count = 2.5f;
    expect_error_at([&] { check(d); }, "ply_count");
    d = ok;
    d.ply_handedness = 0.5f;
    expect_error_at([&] { check(d); }, "ply_handedness");
    d = ok;
    d.ply_radius = 0.6f;  // 0.52 + 0.6 > 1: sticks out of the tube
    expect_error_at([&] { check(d); }, "ply_radius");
    d = ok;
    d.migration_rho_min = 0.9f;
    d.migration_rho_max = 0.8f;
    expect_error_at([&] { check(d); }, "migration_rho_min");
    d = ok;
    d.fiber_radius = std::nanf("");
    expect_error_at([&] { check(d); }, "fiber_radius");
    d = ok;
    d.ply_distance = 0;  // three plies on top of each other
    expect_error_at([&] { check(d); }, "ply_distance");
    try {
        d = ok;
        d.map_resolution = 100.5f;
        check(d);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "scene.json");
        EXPECT_EQ(e.place(), "yarns[0].structure.map_resolution");
        EXPECT_NE(std::string(e.what()).find("whole number"), std::string::npos);
    }
}

}  // namespace
}  // namespace purl
