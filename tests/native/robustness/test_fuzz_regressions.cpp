// Every input a fuzzer found (tests/fuzz/regressions/<target>/) replayed through the same
// check the fuzz target runs (tests/fuzz/fuzz_checks.h): it must now end in a clear
// InputError or an accepted, valid result, and under scripts/test_sanitizers.sh without a
// sanitizer report. Known findings also check the exact message of their fix.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "../../fuzz/fuzz_checks.h"

namespace fs = std::filesystem;

namespace {

const fs::path kRegressions = fs::path(PURL_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
const std::string kFuzzData = std::string(PURL_SOURCE_DIR) + "/tests/fuzz/data";

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `target`'s check on one input; returns the InputError text ("" when accepted).
std::string replay(const std::string& target, const std::string& input) {
    const auto* data = reinterpret_cast<const uint8_t*>(input.data());
    std::string error, broken;
    if (target == "bcc") broken = purl::fuzz::check_bcc(data, input.size(), &error);
    else if (target == "scene_json") broken = purl::fuzz::check_scene_json(input, kFuzzData, &error);
    else if (target == "preset") broken = purl::fuzz::check_preset(data, input.size(), &error);
    else ADD_FAILURE() << "unknown fuzz target folder " << target;
    EXPECT_EQ(broken, "") << target;
    return error;
}

}  // namespace

TEST(FuzzRegressions, EverySavedFindingEndsCleanly) {
    int replayed = 0;
    for (const char* target : {"bcc", "scene_json", "preset"}) {
        const fs::path dir = kRegressions / target;
        if (!fs::exists(dir)) continue;
        for (const auto& entry : fs::directory_iterator(dir)) {
            SCOPED_TRACE(entry.path().string());
            replay(target, bytes_of(entry.path()));
            ++replayed;
        }
    }
    EXPECT_GT(replayed, 0);
}

// fuzz_bcc, first minute: a Bezier file with a coordinate of -1.7e38 (finite) whose basis
// change to B-spline overflowed to infinity; load_bcc returned it and validate_curves caught
// it only later. Now load_bcc names the curve.
TEST(FuzzRegressions, BccBezierConversionOverflowIsAnError) {
    const std::string error = replay("bcc", bytes_of(kRegressions / "bcc" / "bezier_overflow.bcc"));
    EXPECT_NE(error.find("curve 0: coordinates too large: converting them to B-spline control points overflows"),
              std::string::npos)
        << error;
}

// The seeds must be inputs the readers accept, or the fuzzers start from error paths only and
// rarely reach the code behind them. A format change that breaks a seed shows up here:
// regenerate them with tests/fuzz/make_seeds.py.
TEST(FuzzRegressions, SeedCorporaAreAccepted) {
    const fs::path corpus = fs::path(PURL_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
    int seeds = 0;
    for (const char* target : {"bcc", "scene_json", "preset"})
        for (const auto& entry : fs::directory_iterator(corpus / target)) {
            SCOPED_TRACE(entry.path().string());
            EXPECT_EQ(replay(target, bytes_of(entry.path())), "");
            ++seeds;
        }
    EXPECT_GE(seeds, 10);
}

// fuzz_scene_json: a literal beyond the double range escaped parse_scene_text as nlohmann's
// out_of_range 406 (not an InputError).
TEST(FuzzRegressions, JsonNumberOverflowIsAnError) {
    const std::string error = replay("scene_json", bytes_of(kRegressions / "scene_json" / "number_overflow.json"));
    EXPECT_NE(error.find("fuzz.json: line 1, column 29: not valid JSON (number overflow parsing '1e400')"),
              std::string::npos)
        << error;
}

// fuzz_scene_json, CI run of 2026-12-02: a camera whose position and look_at are finite but so far
// apart that their float difference overflows got a NaN frame. look_at now works in double, and
// an up along the view (here also along Y, the first fallback) still gives a frame.
TEST(FuzzRegressions, CameraPlacementsOfDistinctFinitePointsAreFinite) {
    EXPECT_EQ(replay("scene_json", bytes_of(kRegressions / "scene_json" / "camera_far_apart.json")), "");
    EXPECT_EQ(replay("scene_json", bytes_of(kRegressions / "scene_json" / "camera_up_along_y_view.json")), "");
}

// fuzz_bcc, CI run of 2026-12-02: a file whose points are all equal loaded, and only
// validate_curves refused it later. load_bcc now names it.
TEST(FuzzRegressions, BccCollapsedToOnePointIsAnError) {
    const std::string error = replay("bcc", bytes_of(kRegressions / "bcc" / "collapsed_to_one_point.bcc"));
    EXPECT_NE(error.find("is collapsed to one point"), std::string::npos) << error;
}

// fuzz_scene_json, CI run of 2026-12-06: a triangle index of 2.1e31 (a float) was converted to
// uint32_t (undefined behaviour, UBSan). Indices must now be whole numbers.
TEST(FuzzRegressions, TriangleIndexThatIsNoWholeNumberIsAnError) {
    const std::string error =
        replay("scene_json", bytes_of(kRegressions / "scene_json" / "triangle_index_float.json"));
    EXPECT_NE(error.find("meshes[0].triangles: triangle indices must be whole numbers >= 0"),
              std::string::npos)
        << error;
}
