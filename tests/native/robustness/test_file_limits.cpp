// File-level limits: absurd header counts, files of several GB (sparse, never written),
// FIFOs and folders given as files. Each must end in a clear InputError before memory or
// time grows with what the file claims.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <functional>
#include <limits>

#include "io/image_io.h"
#include "robustness_util.h"
#include "scene/bcc.h"
#include "scene/obj_reader.h"
#include "scene/scene_json.h"

using namespace purl;
using namespace purl::robustness;

namespace {

constexpr uint64_t kGiB = uint64_t(1) << 30;

// Writes `header` and extends the file to `size` bytes without writing them (sparse).
std::string sparse_file(const ScratchDir& dir, const std::string& name, const std::string& header, uint64_t size) {
    const std::string path = dir.write(name, header);
    fs::resize_file(path, size);
    return path;
}

// Bytes read by `f`: a reader that stops early reads a few kilobytes of a huge file.
uint64_t bytes_read_by(const std::function<void()>& f) {
    const uint64_t before = bytes_read();
    f();
    return bytes_read() - before;
}

}  // namespace

TEST(FileLimits, BccCountsBeyondTheFileSizeAreRejectedFromTheHeader) {
    ScratchDir dir("counts");
    const std::string body(4 + 12 * 4, '\0');
    // Each count alone far beyond what 52 bytes can hold.
    EXPECT_NE(input_error_of([&] { read_bcc(dir.write("a.bcc", bcc_header("BS", uint64_t(1) << 62, 4) + body)); })
                  .find("declares 4611686018427387904 curves"),
              std::string::npos);
    EXPECT_NE(input_error_of([&] { read_bcc(dir.write("b.bcc", bcc_header("BS", 1, ~uint64_t(0)) + body)); })
                  .find("points, more than the 52 bytes"),
              std::string::npos);
    // Counts whose byte total wraps around 2^64 to exactly the file size: 4 * (2^62 + 1) = 4 mod 2^64.
    const std::string wrapped = input_error_of(
        [&] { read_bcc(dir.write("c.bcc", bcc_header("BS", (uint64_t(1) << 62) + 1, 4) + body)); });
    EXPECT_NE(wrapped.find("curves, more than"), std::string::npos) << wrapped;
    // A curve record claiming INT32_MIN points.
    std::string min_count = bcc_header("BS", 1, 4);
    put_u32(min_count, 0x80000000u);
    min_count += std::string(48, '\0');
    EXPECT_NE(input_error_of([&] { read_bcc(dir.write("d.bcc", min_count)); }).find("declares 2147483648 points"),
              std::string::npos);
}

TEST(FileLimits, BccOfSeveralGigabytesBeyondThePointLimitFailsAtTheHeader) {
    ScratchDir dir("bcc5g");
    // 5 GiB exactly: one curve of (5 GiB - 68) / 12 = 447392421 points, sizes consistent.
    const uint64_t points = (5 * kGiB - 68) / 12;
    ASSERT_EQ(68 + 12 * points, 5 * kGiB);
    const std::string path = sparse_file(dir, "huge.bcc", bcc_header("BS", 1, points), 5 * kGiB);
    const size_t rss_before = peak_resident_bytes();
    std::string error;
    const uint64_t read = bytes_read_by([&] { error = input_error_of([&] { load_bcc(path, 0.01f); }); });
    EXPECT_NE(error.find("at most 268435456 (2^28) per file"), std::string::npos) << error;
    EXPECT_LT(read, uint64_t(1) << 20);
    EXPECT_LT(peak_resident_bytes() - rss_before, size_t(64) << 20);
}

TEST(FileLimits, BccOfGigabytesWithinTheLimitStopsAtTheFirstBadCurve) {
    ScratchDir dir("bcc1g");
    // 2^27 points (1.5 GiB) declared and sized consistently; curve 0 is fine (4 points of
    // zeros), curve 1's count is a zero in the hole of the sparse file.
    const uint64_t points = uint64_t(1) << 27;
    const uint64_t size = 64 + 4 * 2 + 12 * points;
    std::string start = bcc_header("BS", 2, points);
    put_u32(start, 4);
    const std::string path = sparse_file(dir, "big.bcc", start, size);
    const size_t rss_before = peak_resident_bytes();
    std::string error;
    const uint64_t read = bytes_read_by([&] { error = input_error_of([&] { read_bcc(path); }); });
    EXPECT_NE(error.find("curve 1 (byte 116): open B-spline curve cannot have 0 points"), std::string::npos) << error;
    // Not the whole 1.5 GB first (the whole-body read this replaced took seconds and as much memory).
    EXPECT_LT(read, uint64_t(1) << 20);
    EXPECT_LT(peak_resident_bytes() - rss_before, size_t(64) << 20);
}

TEST(FileLimits, ObjOfSeveralGigabytesStopsAtTheFirstOverlongLine) {
    ScratchDir dir("obj5g");
    const std::string path = sparse_file(dir, "huge.obj", "v 0 0 0\n", 5 * kGiB);
    const size_t rss_before = peak_resident_bytes();
    MeshDesc mesh;
    std::string error;
    const uint64_t read = bytes_read_by([&] { error = input_error_of([&] { read_obj(path, mesh); }); });
    EXPECT_NE(error.find("line 2: line longer than 1048576 bytes"), std::string::npos) << error;
    EXPECT_LT(read, uint64_t(4) << 20);  // the first line, and the second up to its limit
    EXPECT_LT(peak_resident_bytes() - rss_before, size_t(64) << 20);
}

TEST(FileLimits, FifosAndFoldersAreNotReadAsFiles) {
    ScratchDir dir("fifo");
    const std::string fifo = dir.file("pipe");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // Opening a FIFO with no writer blocks forever: each reader must refuse it first.
    EXPECT_NE(input_error_of([&] { read_bcc(fifo); }).find("not a regular file"), std::string::npos);
    EXPECT_NE(input_error_of([&] { read_bcc_header(fifo); }).find("not a regular file"), std::string::npos);
    MeshDesc mesh;
    EXPECT_NE(input_error_of([&] { read_obj(fifo, mesh); }).find("not a regular file"), std::string::npos);
    EXPECT_NE(input_error_of([&] { read_image_rgb(fifo); }).find("not a regular file"), std::string::npos);
    EXPECT_NE(input_error_of([&] { load_scene_file(fifo); }).find("not a regular file"), std::string::npos);
    EXPECT_NE(input_error_of([&] { read_bcc(dir.path().string()); }).find("not a regular file"), std::string::npos);
    EXPECT_NE(input_error_of([&] { read_obj(dir.path().string(), mesh); }).find("not a regular file"),
              std::string::npos);
}

TEST(FileLimits, ObjLinesMayEndInCarriageReturns) {
    ScratchDir dir("crlf");
    MeshDesc mesh;
    read_obj(dir.write("quad.obj", "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nf 1 2 3\r\n"), mesh);
    EXPECT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.indices.size(), 3u);
}

// load_scene_file checks the size first: parsing JSON takes about ten times its size.
TEST(FileLimits, SceneJsonOfSeveralGigabytesIsRefusedBeforeReading) {
    ScratchDir dir("json5g");
    const std::string path = sparse_file(dir, "huge.json", "{\"camera\": ", 5 * kGiB);
    const size_t rss_before = peak_resident_bytes();
    const std::string error = input_error_of([&] { load_scene_file(path); });
    EXPECT_NE(error.find("huge.json: file too large: 5368709120 bytes, scene files may have at most 268435456"),
              std::string::npos)
        << error;
    EXPECT_LT(peak_resident_bytes() - rss_before, size_t(64) << 20);
}
