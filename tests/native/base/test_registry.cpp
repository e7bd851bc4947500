// The registry of choosable things (base/registry.h): lists that front doors can trust.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "base/input_error.h"
#include "base/registry.h"

using namespace purl;

TEST(Registry, EveryListHasUniqueNamesAndValuesAndItsDefault) {
    for (const ChoiceList* list : all_choice_lists()) {
        std::set<std::string> names;
        std::set<float> values;
        for (const Choice& c : list->choices) {
            EXPECT_TRUE(names.insert(c.name).second) << list->key << ": " << c.name;
            EXPECT_TRUE(values.insert(c.value).second) << list->key << ": " << c.name;
            EXPECT_NE(std::string(c.doc), "") << list->key << ": " << c.name;
        }
        EXPECT_NE(find_choice(*list, list->default_name), nullptr) << list->key;
    }
}

TEST(Registry, NamesTheChoicesInOrder) {
    EXPECT_EQ(choice_names(ply_methods()), (std::vector<std::string>{"elliptical", "local", "circular"}));
    EXPECT_EQ(choice_names(multiscale_modes()), (std::vector<std::string>{"near", "multi", "far", "auto"}));
    EXPECT_EQ(choice_names_text(yarn_models()), "bysdf, ply or fiber");
    EXPECT_EQ(choice_name(ply_methods(), float(PlyCrossSection::local)), std::string("local"));
}

TEST(Registry, ParsesANameOrSaysWhatItTakes) {
    EXPECT_EQ(parse_choice(ply_methods(), "circular", "s.json", "ply_method"), float(PlyCrossSection::circular));
    try {
        parse_choice(ply_methods(), "oval", "s.json", "ply_method");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "s.json: ply_method: must be elliptical, local or circular, got \"oval\"");
    }
}

TEST(Registry, RenderSettingsHaveKindsRangesAndDefaultsInRange) {
    for (const ParamInfo& s : render_settings()) {
        EXPECT_LE(s.min_value, s.default_value[0]) << s.name;
        EXPECT_GE(s.max_value, s.default_value[0]) << s.name;
        EXPECT_EQ(s.kind == ParamKind::Enum, s.choices != nullptr) << s.name;
    }
    EXPECT_EQ(render_setting("seed").kind, ParamKind::Integer);
    EXPECT_EQ(render_setting("seed").max_value, 2147483647.0);  // exact: the bounds are doubles
    EXPECT_EQ(render_setting("ply_method").choices, &ply_methods());
    EXPECT_THROW(render_setting("samples"), std::out_of_range);
}

TEST(Registry, TwistDirectionsAreASign) {
    ParamInfo p{"ply_handedness", "", 1, -1, 1, {1, 0, 0}, "", 0, false};
    EXPECT_FALSE(p.is_sign());
    p.kind = ParamKind::Enum;
    p.choices = &twist_directions();
    EXPECT_TRUE(p.is_sign());
    p.choices = &ply_methods();
    EXPECT_FALSE(p.is_sign());
}
