// BCC reader and writer: every curve type, round trips, malformed files, the shared data files.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <unordered_map>

#include "base/input_error.h"
#include "scene/bcc.h"

namespace purl {
namespace {

namespace fs = std::filesystem;

// A tiny independent BCC writer, so the reader is not only tested against write_bcc.
struct RawCurve {
    int32_t count;             // as stored: negative for a closed loop
    std::vector<float> xyz;    // 3 per point
};
std::string raw_bcc(const char type[2], uint8_t up, const std::vector<RawCurve>& curves,
                    int64_t curve_count = -1, int64_t point_count = -1) {
    uint64_t points = 0;
    for (const RawCurve& c : curves) points += c.xyz.size() / 3;
    std::string s = "BCC";
    s.push_back(char(0x44));
    s.append(type, 2);
    s.push_back(3);
    s.push_back(char(up));
    auto u64 = [&](uint64_t v) { s.append(reinterpret_cast<const char*>(&v), 8); };
    u64(curve_count >= 0 ? uint64_t(curve_count) : curves.size());
    u64(point_count >= 0 ? uint64_t(point_count) : points);
    s.append(std::string("synthetic test file").append(21, '\0'));
    for (const RawCurve& c : curves) {
        s.append(reinterpret_cast<const char*>(&c.count), 4);
        s.append(reinterpret_cast<const char*>(c.xyz.data()), 4 * c.xyz.size());
    }
    return s;
}

class BccTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("purl_test_bcc_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string put(const std::string& name, const std::string& bytes) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return path;
    }
    // Expects read_bcc to fail with `reason_part` in the reason and `place_part` in the place.
    void expect_error(const std::string& bytes, const std::string& reason_part, const std::string& place_part) {
        const std::string path = put("bad.bcc", bytes);
        try {
            read_bcc(path);
            ADD_FAILURE() << "no error; wanted: " << reason_part;
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), path);
            EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
            EXPECT_NE(e.place().find(place_part), std::string::npos) << e.what();
        }
    }
    fs::path dir_;
};

std::vector<float> line_points(int n, float z = 0) {
    std::vector<float> v;
    for (int i = 0; i < n; ++i) {
        v.push_back(float(i));
        v.push_back(0.3f * float(i % 3));
        v.push_back(z + 0.1f * float(i * i % 5));
    }
    return v;
}

Vec4 point4(const std::vector<float>& xyz, size_t i, float r) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], r}; }

float dist(Vec4 a, Vec4 b) { return length(a.xyz() - b.xyz()); }

// Evaluates segment s of curve c of loaded curves.
Vec4 eval_segment(const YarnCurves& y, size_t c, size_t s, float t) {
    return eval_bspline(&y.control_points[y.segment_first[y.segment_offsets[c] + s]], t);
}

TEST_F(BccTest, CatmullRomOpenAndClosedLoadExactly) {
    const std::vector<float> a = line_points(7), b = line_points(5, 4.0f);
    const std::string path = put("cr.bcc", raw_bcc("C0", 2, {{7, a}, {-5, b}}));
    const BccHeader h = read_bcc_header(path);
    EXPECT_EQ(h.basis, CurveBasis::CatmullRom);
    EXPECT_EQ(h.type, "C0");
    EXPECT_EQ(h.info, "synthetic test file");
    const YarnCurves y = load_bcc(path, 0.25f);
    validate_curves(y, path);
    ASSERT_EQ(y.curve_count(), 2u);
    EXPECT_EQ(y.segment_count(0), 4u);  // open: p1 .. p5
    EXPECT_EQ(y.segment_count(1), 5u);  // closed: whole loop
    EXPECT_EQ(y.closed[1], 1);
    for (size_t s = 0; s < 4; ++s) {
        const Vec4 cr[4] = {point4(a, s, 0.25f), point4(a, s + 1, 0.25f), point4(a, s + 2, 0.25f), point4(a, s + 3, 0.25f)};
        for (float t : {0.0f, 0.3f, 1.0f}) EXPECT_LT(dist(eval_segment(y, 0, s, t), eval_catmull_rom(cr, t)), 1e-5f);
    }
    EXPECT_LT(dist(eval_segment(y, 1, 0, 0), point4(b, 0, 0)), 1e-5f);
    EXPECT_NEAR(eval_segment(y, 1, 2, 0.5f).w, 0.25f, 1e-6f);
    EXPECT_EQ(y.curve_ids[1], 1);
}

TEST_F(BccTest, BSplinePolylineAndBezierLoad) {
    const std::vector<float> a = line_points(6), b = line_points(4, 2.0f), c = line_points(7);
    {
        const YarnCurves y = load_bcc(put("bs.bcc", raw_bcc("BS", 2, {{6, a}, {-4, b}})), 1.0f);
        ASSERT_EQ(y.curve_count(), 2u);
        EXPECT_EQ(y.segment_count(0), 3u);
        EXPECT_EQ(y.segment_count(1), 4u);                                   // closed: n segments
        EXPECT_EQ(y.curve_offsets[2] - y.curve_offsets[1], 7u);              // 4 + 3 wrapped
        EXPECT_EQ(y.control_points[0].x, a[0]);                              // passed through
    }
    {
        const YarnCurves y = load_bcc(put("pl.bcc", raw_bcc("PL", 2, {{6, a}, {-4, b}})), 1.0f);
        ASSERT_EQ(y.curve_count(), 2u);
        EXPECT_EQ(y.segment_count(0), 5u);
        EXPECT_EQ(y.segment_count(1), 4u);
        for (size_t i = 0; i < 5; ++i) EXPECT_LT(dist(eval_segment(y, 0, i, 0), point4(a, i, 1)), 1e-5f);
        EXPECT_LT(dist(eval_segment(y, 0, 4, 1), point4(a, 5, 1)), 1e-5f);
        EXPECT_LT(dist(eval_segment(y, 1, 3, 1), point4(b, 0, 1)), 1e-5f);  // closes on p0
    }
    {
        const std::vector<float> d = line_points(6, 1.0f);
        const YarnCurves y = load_bcc(put("bz.bcc", raw_bcc("BZ", 2, {{7, c}, {-6, d}})), 1.0f);
        ASSERT_EQ(y.curve_count(), 2u);
        EXPECT_EQ(y.segment_count(0), 2u);
        EXPECT_EQ(y.segment_count(1), 2u);
        const Vec4 bz[4] = {point4(c, 3, 1), point4(c, 4, 1), point4(c, 5, 1), point4(c, 6, 1)};
        for (float t : {0.0f, 0.6f, 1.0f}) EXPECT_LT(dist(eval_segment(y, 0, 1, t), eval_bezier(bz, t)), 1e-5f);
        EXPECT_LT(dist(eval_segment(y, 1, 1, 1), point4(d, 0, 1)), 1e-5f);
    }
    {
        // A closed Bezier of one segment (3 points) converts to 4 control points at 0, which
        // look like a chain but are not wrapped: it must stay one segment (found by fuzzing).
        const std::vector<float> e = {0, 0, 0, 1, 0, 0, 1, 1, 0};
        const YarnCurves y = load_bcc(put("bz1.bcc", raw_bcc("BZ", 1, {{-3, e}})), 1.0f);
        ASSERT_EQ(y.curve_count(), 1u);
        EXPECT_EQ(y.segment_count(0), 1u);
        EXPECT_EQ(y.point_count(), 4u);
        EXPECT_NO_THROW(validate_curves(y, "bz1.bcc"));
        EXPECT_LT(dist(eval_segment(y, 0, 0, 1), point4(e, 0, 1)), 1e-5f);  // closes on p0
    }
}

TEST_F(BccTest, YUpBecomesZUpByAProperRotation) {
    const std::vector<float> a = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    const YarnCurves y = load_bcc(put("yup.bcc", raw_bcc("BS", 1, {{4, a}})), 1.0f);
    const Vec4& p = y.control_points[0];
    EXPECT_EQ(p.x, 1.0f);
    EXPECT_EQ(p.y, -3.0f);
    EXPECT_EQ(p.z, 2.0f);
    // The images of the axes form a right-handed orthonormal frame, and old up becomes +Z.
    const Vec3 ex = bcc_y_up_to_z_up({1, 0, 0}), ey = bcc_y_up_to_z_up({0, 1, 0}), ez = bcc_y_up_to_z_up({0, 0, 1});
    EXPECT_FLOAT_EQ(dot(cross(ex, ey), ez), 1.0f);
    EXPECT_FLOAT_EQ(length(ex) * length(ey) * length(ez), 1.0f);
    EXPECT_FLOAT_EQ(dot(ex, ey) + dot(ey, ez) + dot(ez, ex), 0.0f);
    EXPECT_FLOAT_EQ(ey.z, 1.0f);
}

TEST_F(BccTest, WriteThenReadRoundTrips) {
    YarnCurves y;
    std::vector<Vec4> open, loop;
    for (int i = 0; i < 9; ++i) open.emplace_back(0.1f * i, std::sin(float(i)), 0.5f, 0.01f);
    for (int i = 0; i < 6; ++i) loop.emplace_back(std::cos(float(i)), std::sin(float(i)), -1.0f, 0.01f);
    y.add_curve(open.data(), open.size(), false);
    y.add_curve(loop.data(), loop.size(), true);
    // A Catmull-Rom loop converted exactly has independent segments: written one by one.
    y.add(to_bspline_segments(CurveBasis::CatmullRom, loop.data(), loop.size(), true), true, 7);
    const std::string path = (dir_ / "round.bcc").string();
    write_bcc(path, y, "round trip");

    const BccCurves file = read_bcc(path);
    EXPECT_EQ(file.header.type, "BS");
    EXPECT_EQ(file.header.up_axis, 2);
    EXPECT_EQ(file.header.info, "round trip");
    ASSERT_EQ(file.curve_count(), 2u + 6u);
    EXPECT_EQ(file.header.point_count, 9u + 6u + 6u * 4u);
    EXPECT_EQ(file.closed[1], 1);
    EXPECT_EQ(fs::file_size(path), 64u + 4u * 8u + 12u * file.header.point_count);

    const YarnCurves back = load_bcc(path, 0.01f);
    ASSERT_EQ(back.curve_offsets[2], y.curve_offsets[2]);  // chains come back point for point
    for (uint32_t i = 0; i < y.curve_offsets[2]; ++i) EXPECT_EQ(std::memcmp(&back.control_points[i], &y.control_points[i], 16), 0);
    // The segment curves come back as open 4-point curves tracing the same shape.
    for (size_t s = 0; s < 6; ++s)
        for (float t : {0.0f, 0.5f, 1.0f})
            EXPECT_LT(dist(eval_segment(back, 2 + s, 0, t), eval_segment(y, 2, s, t)), 1e-6f);
}

TEST_F(BccTest, MalformedFilesNameTheReason) {
    const std::vector<float> a = line_points(5);
    const std::string good = raw_bcc("BS", 2, {{5, a}, {-4, line_points(4)}});
    ASSERT_NO_THROW(read_bcc(put("good.bcc", good)));

    expect_error("", "fewer than the 64-byte", "byte 0");
    expect_error(good.substr(0, 40), "fewer than the 64-byte", "byte 40");
    expect_error(good.substr(0, good.size() - 1), "truncated", "byte");
    expect_error(good + "x", "(extra bytes at the end)", "byte");
    std::string bad = good;
    bad[1] = 'X';
    expect_error(bad, "signature", "byte 0");
    bad = good;
    bad[3] = 0x88;
    expect_error(bad, "0x44", "byte 3");
    bad = good;
    bad[4] = 'X';
    bad[5] = 'Y';
    expect_error(bad, "unknown curve type 'XY'", "byte 4");
    bad = good;
    bad[6] = 2;
    expect_error(bad, "dimensions", "byte 6");
    bad = good;
    bad[7] = 0;
    expect_error(bad, "up axis", "byte 7");
    // Absurd counts are rejected before anything is allocated.
    expect_error(raw_bcc("BS", 2, {{5, a}}, int64_t(1) << 60, 5), "declares 1152921504606846976 curves", "byte 8");
    expect_error(raw_bcc("BS", 2, {{5, a}}, 1, int64_t(1) << 61), "declares 2305843009213693952 points", "byte 16");
    expect_error(good.substr(0, good.size() - 13), "truncated", "byte");
    expect_error(raw_bcc("BS", 2, {}, 0, 0), "no curves", "byte 8");
    // Per-curve problems name the curve and its byte offset.
    expect_error(raw_bcc("BS", 2, {{20, a}, {-4, line_points(4)}}), "declares 20 points but only 9", "curve 0 (byte 64)");
    expect_error(raw_bcc("BS", 2, {{5, a}, {-40, line_points(4)}}), "declares 40 points", "curve 1 (byte 128)");
    expect_error(raw_bcc("BS", 2, {{std::numeric_limits<int32_t>::min(), line_points(5)}}), "declares 2147483648", "curve 0");
    expect_error(raw_bcc("BS", 2, {{3, line_points(3)}}), "open B-spline curve cannot have 3 points", "curve 0");
    expect_error(raw_bcc("BS", 2, {{0, {}}, {5, a}}), "cannot have 0 points", "curve 0");
    expect_error(raw_bcc("BZ", 2, {{6, line_points(6)}}), "3k+1", "curve 0");
    expect_error(raw_bcc("PL", 2, {{-2, line_points(2)}}), "closed polyline curve cannot have 2", "curve 0");
    // Sizes agree with the header, but the curves use fewer points than it declares.
    expect_error(raw_bcc("PL", 2, {{2, line_points(5)}}), "curves hold 2 points but the header declares 5", "byte 92");
    std::vector<float> nan_points = a;
    nan_points[7] = std::nanf("");
    expect_error(raw_bcc("BS", 2, {{5, nan_points}}), "not finite", "curve 0, point 2 (byte 92)");
    nan_points[7] = std::numeric_limits<float>::infinity();
    expect_error(raw_bcc("BS", 2, {{5, nan_points}}), "not finite", "point 2");

    EXPECT_THROW(read_bcc((dir_ / "missing.bcc").string()), InputError);
    EXPECT_THROW(load_bcc(put("r.bcc", good), 0.0f), InputError);
    EXPECT_THROW(load_bcc(put("r.bcc", good), std::nanf("")), InputError);
}

// ---- the shared data files ----

std::string shared(const char* name) { return std::string(PURL_SHARED_DATA_DIR) + "/" + name; }

// Points along every curve: each segment at t = 0, 1/4, 1/2, 3/4.
struct Samples {
    std::vector<Vec3> p;
    std::vector<uint32_t> curve;
};
Samples sample_curves(const YarnCurves& y) {
    Samples s;
    for (size_t c = 0; c < y.curve_count(); ++c)
        for (uint32_t k = y.segment_offsets[c]; k < y.segment_offsets[c + 1]; ++k)
            for (float t : {0.0f, 0.25f, 0.5f, 0.75f}) {
                s.p.push_back(eval_bspline(&y.control_points[y.segment_first[k]], t).xyz());
                s.curve.push_back(uint32_t(c));
            }
    return s;
}

// For every sample, the distance to the nearest sample of another curve (uniform grid).
std::vector<float> nearest_other_curve(const Samples& s, float cell) {
    auto key = [](int x, int y, int z) {
        return (int64_t(x) & 0x1fffff) | (int64_t(y) & 0x1fffff) << 21 | (int64_t(z) & 0x1fffff) << 42;
    };
    std::unordered_map<int64_t, std::vector<uint32_t>> grid;
    std::vector<int> cx(s.p.size()), cy(s.p.size()), cz(s.p.size());
    for (size_t i = 0; i < s.p.size(); ++i) {
        cx[i] = int(std::floor(s.p[i].x / cell));
        cy[i] = int(std::floor(s.p[i].y / cell));
        cz[i] = int(std::floor(s.p[i].z / cell));
        grid[key(cx[i], cy[i], cz[i])].push_back(uint32_t(i));
    }
    std::vector<float> out;
    out.reserve(s.p.size());
    for (size_t i = 0; i < s.p.size(); ++i) {
        float best = std::numeric_limits<float>::infinity();
        for (int r = 0; r < 40 && !(best <= r * cell); ++r)  // shell r holds every point within r*cell
            for (int dx = -r; dx <= r; ++dx)
                for (int dy = -r; dy <= r; ++dy)
                    for (int dz = -r; dz <= r; ++dz) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
                        auto it = grid.find(key(cx[i] + dx, cy[i] + dy, cz[i] + dz));
                        if (it == grid.end()) continue;
                        for (uint32_t j : it->second)
                            if (s.curve[j] != s.curve[i]) best = std::min(best, length(s.p[j] - s.p[i]));
                    }
        if (std::isfinite(best)) out.push_back(best);
    }
    return out;
}

float percentile(std::vector<float> v, double q) {
    std::sort(v.begin(), v.end());
    return v[size_t(q * double(v.size() - 1))];
}

TEST(BccData, GloveLoads) {
    const std::string path = shared("glove.bcc");
    if (!fs::exists(path)) GTEST_SKIP() << "no shared data at " << path;
    const auto start = std::chrono::steady_clock::now();
    const BccCurves file = read_bcc(path);
    const double read_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(file.header.basis, CurveBasis::CatmullRom);
    EXPECT_EQ(file.header.up_axis, 1);
    EXPECT_EQ(file.curve_count(), 70u);
    EXPECT_EQ(file.points.size(), 58537u);
    EXPECT_TRUE(std::all_of(file.closed.begin(), file.closed.end(), [](uint8_t c) { return c == 1; }));

    const YarnCurves y = load_bcc(path, 0.12f);
    validate_curves(y, path);
    EXPECT_EQ(y.curve_count(), 70u);
    EXPECT_EQ(y.segment_count(), 58537u);  // closed Catmull-Rom: one segment per point
    Vec3 lo(1e30f), hi(-1e30f);
    for (const Vec3& p : file.points) {
        lo = min(lo, bcc_y_up_to_z_up(p));
        hi = max(hi, bcc_y_up_to_z_up(p));
    }
    const Vec3 size = hi - lo;
    // REFERENCE: about 28 x 35 x 26 in the file's Y-up axes, so 28 x 26 x 35 once Z is up.
    EXPECT_NEAR(size.x, 28.0f, 1.5f);
    EXPECT_NEAR(size.y, 26.0f, 1.5f);
    EXPECT_NEAR(size.z, 35.0f, 1.5f);
    std::cout << "glove.bcc: read " << read_ms << " ms, bbox " << size.x << " x " << size.y << " x " << size.z
              << " (Z-up)\n";
}

TEST(BccData, KnitTubeLoads) {
    const std::string path = shared("knittubeinit.bcc");
    if (!fs::exists(path)) GTEST_SKIP() << "no shared data at " << path;
    const BccCurves file = read_bcc(path);
    EXPECT_EQ(file.header.basis, CurveBasis::BSpline);
    EXPECT_EQ(file.curve_count(), 39u);
    EXPECT_EQ(file.points.size(), 18228u);
    const YarnCurves y = load_bcc(path, 0.1f);
    validate_curves(y, path);
    EXPECT_EQ(y.segment_count(), 18228u);       // closed chains: one segment per point
    EXPECT_EQ(y.point_count(), 18228u + 3 * 39u);  // plus 3 wrapped points per loop
}

// Measures the spacing between distinct yarns so a radius can be chosen: neighbouring yarns
// just touch at radius ~ d/2 where d is the distance between them where they are closest.
TEST(BccData, DistanceBetweenDistinctYarns) {
    for (const char* name : {"glove.bcc", "knittubeinit.bcc"}) {
        const std::string path = shared(name);
        if (!fs::exists(path)) GTEST_SKIP() << "no shared data at " << path;
        const YarnCurves y = load_bcc(path, 1.0f);
        const Samples s = sample_curves(y);
        std::vector<float> along;  // spacing of consecutive samples on one curve
        for (size_t i = 1; i < s.p.size(); ++i)
            if (s.curve[i] == s.curve[i - 1]) along.push_back(length(s.p[i] - s.p[i - 1]));
        const float step = 4 * percentile(along, 0.5);  // one segment
        const std::vector<float> d = nearest_other_curve(s, 2 * step);
        ASSERT_GT(d.size(), s.p.size() / 2);
        const float p10 = percentile(d, 0.1), med = percentile(d, 0.5), p90 = percentile(d, 0.9);
        std::cout << name << ": segment length (median) " << step << ", nearest other yarn: min "
                  << percentile(d, 0.0) << ", p10 " << p10 << ", median " << med << ", p90 " << p90 << "\n";
        RecordProperty(std::string(name) + "_median_distinct_yarn_distance", std::to_string(med));
        // Neighbouring yarns of a knit are roughly a yarn diameter apart: far more than zero,
        // and within a few segment lengths.
        EXPECT_GT(p10, 0.2f * step);
        EXPECT_LT(med, 10.0f * step);
    }
}

// How far a C2 chain through the Catmull-Rom points (one chain per yarn, 4x fewer points)
// would move the glove's yarns from their exact curves, relative to the point spacing.
TEST(BccData, GloveChainApproximationError) {
    const std::string path = shared("glove.bcc");
    if (!fs::exists(path)) GTEST_SKIP() << "no shared data at " << path;
    const BccCurves file = read_bcc(path);
    float worst = 0, spacing_sum = 0, from_polyline = 0;
    size_t spacing_count = 0;
    for (size_t c = 0; c < file.curve_count(); ++c) {
        std::vector<Vec4> p;
        for (uint32_t i = file.curve_offsets[c]; i < file.curve_offsets[c + 1]; ++i) p.emplace_back(file.points[i], 1.0f);
        const size_t n = p.size();
        const BSplineSegments exact = to_bspline_segments(CurveBasis::CatmullRom, p.data(), n, true);
        const BSplineSegments chain = to_bspline_segments(CurveBasis::Polyline, p.data(), n, true);
        for (size_t s = 0; s < n; ++s) {
            const Vec3 a = p[s].xyz(), b = p[(s + 1) % n].xyz();
            spacing_sum += length(b - a);
            ++spacing_count;
            for (int k = 1; k < 8; ++k) {
                const Vec3 q = chain.evaluate(s, k / 8.0f).xyz();
                worst = std::max(worst, length(exact.evaluate(s, k / 8.0f).xyz() - q));
                // Deviation of the interpolating chain from the polyline itself.
                const float u = clamp(dot(q - a, b - a) / std::max(1e-30f, dot(b - a, b - a)), 0.0f, 1.0f);
                from_polyline = std::max(from_polyline, length(q - (a + (b - a) * u)));
            }
        }
    }
    const float spacing = spacing_sum / float(spacing_count);
    std::cout << "glove.bcc: C2 chain vs exact Catmull-Rom: max deviation " << worst << " (" << worst / spacing
              << " of the mean point spacing " << spacing << "); chain vs the points as a polyline: max "
              << from_polyline << "\n";
    EXPECT_GT(worst, 0.0f);  // the two curves do differ: the chain is an approximation
    EXPECT_LT(worst, spacing);
}

}  // namespace
}  // namespace purl
