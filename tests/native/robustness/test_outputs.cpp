// Nothing lost: images are written to a temporary sibling and renamed, so a failed write
// leaves the previous image as it was and no temporary behind, and writes of the same
// output from several threads at once each leave a whole file. Output paths that could not
// be written are refused before a render; a process terminated while writing leaves nothing.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
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

TEST(Outputs, BadOutputPathsAreRefusedBeforeAnyWork) {
    ScratchDir dir("output-paths");
    auto reason = [](const std::string& path, bool png_only = false) {
        return input_error_of([&] { check_output_path(path, "-o", png_only); });
    };
    EXPECT_EQ(reason(dir.file("fine.exr")), "");
    EXPECT_EQ(reason(dir.file("fine.PNG"), true), "");
    EXPECT_NE(reason(dir.file("missing/x.exr")).find("does not exist"), std::string::npos);
    EXPECT_NE(reason(dir.file("x.jpg")).find("must end in .exr or .png"), std::string::npos);
    EXPECT_NE(reason(dir.file("x.exr"), true).find("must end in .png"), std::string::npos);
    fs::create_directory(dir.file("folder.exr"));
    EXPECT_NE(reason(dir.file("folder.exr")).find("is a folder"), std::string::npos);
    EXPECT_NE(reason("/proc/x.exr").find("cannot create a file in /proc"), std::string::npos);
    EXPECT_EQ(files_in(dir.path()), 1u);  // the probe files are gone again
}

// A process killed (SIGTERM) in the middle of writing an image leaves no temporary behind,
// when its handler calls discard_partial_output as the CLI's does.
TEST(Outputs, TerminationDuringAWriteLeavesNoTemporary) {
    ScratchDir dir("terminated");
    const std::string out = dir.file("image.exr");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        std::signal(SIGTERM, [](int sig) {
            discard_partial_output();
            std::signal(sig, SIG_DFL);
            std::raise(sig);
        });
        write_file_atomically(out, [](const std::string& tmp) {
            std::ofstream(tmp) << "half an image";
            std::raise(SIGTERM);
            std::ofstream(tmp, std::ios::app) << "never";
        });
        _exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    EXPECT_EQ(files_in(dir.path()), 0u);
}
