// Nothing lost: images are written to a temporary sibling and renamed, so a failed write
// leaves the previous image as it was and no temporary behind, and writes of the same
// output from several threads at once each leave a whole file.
#include <gtest/gtest.h>

#include <thread>

#include "io/image_io.h"
#include "robustness_util.h"

using namespace purl;
using namespace purl::robustness;

namespace {

RenderImage grey_image(int width, int height, float value) {
    RenderImage image;
    image.width = width;
    image.height = height;
    image.passes.push_back({"Combined", {"R", "G", "B", "A"}, std::vector<float>(size_t(width) * height * 4, value)});
    image.passes.push_back({"Depth", {"Z"}, std::vector<float>(size_t(width) * height, 2.0f)});
    return image;
}

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

size_t files_in(const fs::path& dir) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

TEST(Outputs, AFailedWriteKeepsThePreviousImageAndLeavesNoTemporary) {
    ScratchDir dir("outputs");
    const std::string png = dir.file("image.png");
    write_png(png, grey_image(8, 8, 0.5f));
    const std::string before = bytes_of(png);
    ASSERT_FALSE(before.empty());
    // No Combined pass: write_png refuses before touching anything.
    RenderImage no_combined = grey_image(8, 8, 0.5f);
    no_combined.passes.erase(no_combined.passes.begin());
    EXPECT_THROW(write_png(png, no_combined), std::exception);
    // A folder where the output should go: the rename fails after the temporary was written.
    const std::string folder = dir.file("taken.exr");
    fs::create_directories(fs::path(folder) / "inside");
    EXPECT_THROW(write_multilayer_exr(folder, grey_image(8, 8, 0.5f), "ViewLayer"), std::exception);
    EXPECT_TRUE(fs::is_directory(fs::path(folder) / "inside"));
    EXPECT_EQ(bytes_of(png), before);
    EXPECT_EQ(files_in(dir.path()), 2u) << "a temporary was left behind";
}

TEST(Outputs, ConcurrentWritesOfOneOutputEachLeaveAWholeFile) {
    ScratchDir dir("concurrent");
    const std::string exr = dir.file("same.exr");
    std::vector<std::thread> writers;
    for (int i = 0; i < 4; ++i)
        writers.emplace_back([&, i] {
            for (int k = 0; k < 5; ++k) write_multilayer_exr(exr, grey_image(64, 64, 0.1f * (i + 1)), "ViewLayer");
        });
    for (std::thread& t : writers) t.join();
    const ImageRGB read = read_image_rgb(exr);
    ASSERT_EQ(read.width, 64);
    // Whichever writer renamed last, every pixel comes from that one image.
    for (float v : read.rgb) EXPECT_EQ(v, read.rgb[0]);
    EXPECT_EQ(files_in(dir.path()), 1u) << "a temporary was left behind";
}
