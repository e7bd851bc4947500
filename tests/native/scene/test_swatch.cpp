// Generated swatches: yarns never intersect, knit loops interlock, weaves follow their pattern.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <unordered_map>

#include "base/input_error.h"
#include "math/bspline.h"
#include "math/spline_convert.h"
#include "scene/swatch.h"

namespace purl {
namespace {

constexpr int kSamplesPerSegment = 12;

struct Sample {
    Vec3 p;
    uint32_t curve;
    float arc;  // arc length from the curve's start, m
};

std::vector<Sample> sample(const YarnCurves& y) {
    std::vector<Sample> out;
    for (size_t c = 0; c < y.curve_count(); ++c) {
        float arc = 0;
        Vec3 prev;
        bool first = true;
        for (uint32_t s = y.segment_offsets[c]; s < y.segment_offsets[c + 1]; ++s)
            for (int k = 0; k < kSamplesPerSegment; ++k) {
                const Vec3 p = eval_bspline(&y.control_points[y.segment_first[s]], float(k) / kSamplesPerSegment).xyz();
                if (!first) arc += length(p - prev);
                first = false;
                prev = p;
                out.push_back({p, uint32_t(c), arc});
            }
    }
    return out;
}

// Smallest distance between samples of different curves, and between samples of one curve
// further apart along it than `min_arc`; pairs further apart than `reach` are not looked at.
struct Clearance {
    float between = std::numeric_limits<float>::infinity();
    float within = std::numeric_limits<float>::infinity();
};
Clearance clearance(const std::vector<Sample>& s, float reach, float min_arc) {
    auto key = [](int x, int y, int z) {
        return (int64_t(x) & 0x1fffff) | (int64_t(y) & 0x1fffff) << 21 | (int64_t(z) & 0x1fffff) << 42;
    };
    auto cell = [&](float v) { return int(std::floor(v / reach)); };
    std::unordered_map<int64_t, std::vector<uint32_t>> grid;
    for (size_t i = 0; i < s.size(); ++i) grid[key(cell(s[i].p.x), cell(s[i].p.y), cell(s[i].p.z))].push_back(uint32_t(i));
    Clearance c;
    for (size_t i = 0; i < s.size(); ++i) {
        const int x = cell(s[i].p.x), y = cell(s[i].p.y), z = cell(s[i].p.z);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    auto it = grid.find(key(x + dx, y + dy, z + dz));
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second) {
                        if (j <= i) continue;
                        const float d = length(s[j].p - s[i].p);
                        if (s[j].curve != s[i].curve) c.between = std::min(c.between, d);
                        else if (std::fabs(s[j].arc - s[i].arc) > min_arc) c.within = std::min(c.within, d);
                    }
                }
    }
    return c;
}

// Smallest radius of curvature over all segments, |r'|^3 / |r' x r''|.
float min_curvature_radius(const YarnCurves& y) {
    float best = std::numeric_limits<float>::infinity();
    for (uint32_t first : y.segment_first) {
        Vec3 cp[4];
        for (int i = 0; i < 4; ++i) cp[i] = y.control_points[first + i].xyz();
        for (int k = 0; k <= kSamplesPerSegment; ++k) {
            const float t = float(k) / kSamplesPerSegment;
            const Vec3 d1 = bspline_combine(cp, bspline_basis_derivative(t));
            const Vec3 d2 = bspline_combine(cp, bspline_basis_second_derivative(t));
            const float k_times = length(cross(d1, d2));
            if (k_times > 0) best = std::min(best, length(d1) * dot(d1, d1) / k_times);
        }
    }
    return best;
}

struct Bounds {
    Vec3 lo{1e30f}, hi{-1e30f};
};
Bounds bounds(const std::vector<Sample>& s) {
    Bounds b;
    for (const Sample& x : s) {
        b.lo = min(b.lo, x.p);
        b.hi = max(b.hi, x.p);
    }
    return b;
}

// The checks every swatch must pass, with R the yarn radius.
void expect_no_intersections(const YarnCurves& y, float radius, const char* what) {
    validate_curves(y, what);
    const std::vector<Sample> s = sample(y);
    const Clearance c = clearance(s, 3 * radius, 3 * radius);
    const float rc = min_curvature_radius(y);
    std::cout << what << ": " << y.curve_count() << " curves, clearance between yarns " << c.between / radius
              << " R, within a yarn " << c.within / radius << " R, min curvature radius " << rc / radius << " R\n";
    EXPECT_GE(c.between, 1.9f * radius) << what;
    EXPECT_GE(c.within, 1.9f * radius) << what;  // no part of a yarn runs into another part
    EXPECT_GE(rc, radius) << what;
    const Bounds b = bounds(s);
    const Vec3 size = b.hi - b.lo, centre = (b.hi + b.lo) * 0.5f;
    EXPECT_GT(size.x, 0.02f) << what;  // about 2-3 cm across at the default radius
    EXPECT_LT(size.x, 0.035f) << what;
    EXPECT_GT(size.y, 0.02f) << what;
    EXPECT_LT(size.y, 0.035f) << what;
    EXPECT_LT(size.z, 10 * radius) << what;  // a sheet in the XY plane
    EXPECT_LT(length(centre), 0.1f * size.x) << what;
}

TEST(Swatch, DefaultKnitDoesNotIntersect) {
    const SwatchOptions opt;
    expect_no_intersections(generate_swatch(SwatchKind::Knit, opt), opt.yarn_radius, "knit");
}

TEST(Swatch, WeavesDoNotIntersect) {
    SwatchOptions opt;
    expect_no_intersections(generate_swatch(SwatchKind::Plain, opt), opt.yarn_radius, "plain");
    expect_no_intersections(generate_swatch(SwatchKind::Twill, opt), opt.yarn_radius, "twill 2/1");
    opt.twill_under = 2;
    expect_no_intersections(generate_swatch(SwatchKind::Twill, opt), opt.yarn_radius, "twill 2/2");
    expect_no_intersections(generate_swatch(SwatchKind::Satin, opt), opt.yarn_radius, "satin");
}

TEST(Swatch, ScaledRadiusAndLooserSpacingStayClear) {
    SwatchOptions opt;
    opt.yarn_radius = 2e-4f;
    opt.courses = 4;
    opt.wales = 3;
    opt.spacing = 1.5f * default_swatch_spacing(SwatchKind::Knit, opt.yarn_radius);
    const YarnCurves y = generate_swatch(SwatchKind::Knit, opt);
    const Clearance c = clearance(sample(y), 3 * opt.yarn_radius, 3 * opt.yarn_radius);
    EXPECT_GE(c.between, 1.9f * 1.5f * opt.yarn_radius);  // the whole shape scales with the spacing
    EXPECT_EQ(y.control_points[0].w, opt.yarn_radius);
}

// Linking number of two closed polylines: half the sum of signed crossings in the XY projection.
float linking_number(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    float sum = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const Vec3 p = a[i], r = a[(i + 1) % a.size()] - p;
        for (size_t j = 0; j < b.size(); ++j) {
            const Vec3 q = b[j], s = b[(j + 1) % b.size()] - q;
            const float den = r.x * s.y - r.y * s.x;
            if (den == 0) continue;
            const Vec3 qp = q - p;
            const float u = (qp.x * s.y - qp.y * s.x) / den, v = (qp.x * r.y - qp.y * r.x) / den;
            if (u < 0 || u >= 1 || v < 0 || v >= 1) continue;
            const float za = p.z + u * r.z, zb = q.z + v * s.z;
            sum += (den > 0 ? 1.0f : -1.0f) * (za > zb ? 1.0f : -1.0f);
        }
    }
    return 0.5f * sum;
}

// Samples segments [first, last) of curve c, then closes the piece with two long legs
// running in +Y (up) or -Y (down) so the closure stays clear of the other piece.
std::vector<Vec3> closed_piece(const YarnCurves& y, size_t c, uint32_t first, uint32_t last, float reach_y,
                               float z_shift = 0) {
    std::vector<Vec3> out;
    for (uint32_t s = first; s < last; ++s)
        for (int k = 0; k < 16; ++k)
            out.push_back(eval_bspline(&y.control_points[y.segment_first[y.segment_offsets[c] + s]], k / 16.0f).xyz());
    out.push_back(eval_bspline(&y.control_points[y.segment_first[y.segment_offsets[c] + last - 1]], 1.0f).xyz());
    const Vec3 start = out.front(), end = out.back();
    out.push_back(Vec3(end.x, end.y + reach_y, end.z));
    out.push_back(Vec3(start.x, start.y + reach_y, start.z));
    for (Vec3& p : out) p.z += z_shift;
    return out;
}

TEST(Swatch, KnitLoopsInterlock) {
    SwatchOptions opt;
    opt.courses = 4;
    opt.wales = 4;
    const YarnCurves y = generate_swatch(SwatchKind::Knit, opt);
    ASSERT_EQ(y.curve_count(), 4u);
    const uint32_t per_loop = y.segment_count(0) / opt.wales;  // segments per loop (t in [0, 2pi))
    ASSERT_EQ(per_loop * opt.wales, y.segment_count(0));
    const float far = 1.0f;  // m, far beyond the swatch
    for (size_t c = 0; c + 1 < y.curve_count(); ++c)
        for (uint32_t w = 0; w < uint32_t(opt.wales); ++w) {
            // Loop w of course c, closed far below, against each half of loop w of course c+1
            // (sinker to head, head to sinker), closed far above: each half passes through
            // the loop below exactly once, in opposite directions.
            const std::vector<Vec3> loop = closed_piece(y, c, w * per_loop, (w + 1) * per_loop, -far);
            const std::vector<Vec3> left = closed_piece(y, c + 1, w * per_loop, w * per_loop + per_loop / 2, far);
            const std::vector<Vec3> right = closed_piece(y, c + 1, w * per_loop + per_loop / 2, (w + 1) * per_loop, far);
            EXPECT_EQ(std::fabs(linking_number(loop, left)), 1.0f) << "course " << c << " wale " << w;
            EXPECT_EQ(linking_number(loop, left), -linking_number(loop, right)) << "course " << c << " wale " << w;
        }
    // Control: the same course lifted clear in front of the one below does not link.
    const std::vector<Vec3> loop = closed_piece(y, 0, 0, per_loop, -far);
    const std::vector<Vec3> lifted = closed_piece(y, 1, 0, per_loop / 2, far, 20 * opt.yarn_radius);
    EXPECT_EQ(linking_number(loop, lifted), 0.0f);
}

// Warp j's height at weft i: warps come first, each crossing at segment 1 + 2i (nodes are
// the start, then crossing / midpoint alternately).
float warp_height(const YarnCurves& y, int j, int i) {
    return eval_bspline(&y.control_points[y.segment_first[y.segment_offsets[j] + 1 + 2 * i]], 0.0f).z;
}
float weft_height(const YarnCurves& y, int warps, int i, int j) {
    return eval_bspline(&y.control_points[y.segment_first[y.segment_offsets[warps + i] + 1 + 2 * j]], 0.0f).z;
}

TEST(Swatch, WeavesFollowTheirPattern) {
    SwatchOptions opt;
    opt.warps = 10;
    opt.wefts = 10;
    for (SwatchKind kind : {SwatchKind::Plain, SwatchKind::Twill, SwatchKind::Satin}) {
        const YarnCurves y = generate_swatch(kind, opt);
        ASSERT_EQ(y.curve_count(), 20u);
        for (int j = 0; j < opt.warps; ++j) {
            int overs_in_window = 0;
            for (int i = 0; i < opt.wefts; ++i) {
                const float zw = warp_height(y, j, i), zf = weft_height(y, opt.warps, i, j);
                EXPECT_NEAR(zw, -zf, 1e-6f);                            // one over, one under
                EXPECT_NEAR(std::fabs(zw), 1.15f * opt.yarn_radius, 1e-6f);  // at the crimp height
                const bool over = zw > 0;
                if (kind == SwatchKind::Plain) {
                    EXPECT_EQ(over, (i + j) % 2 == 0);
                } else if (kind == SwatchKind::Twill) {
                    EXPECT_EQ(over, (i + j) % 3 < 2);  // 2/1, diagonal
                }
                if (i < 5) overs_in_window += over;
            }
            if (kind == SwatchKind::Satin) {
                EXPECT_EQ(overs_in_window, 4) << "warp " << j;  // floats over 4
            }
        }
        if (kind == SwatchKind::Satin) {  // interlacings never touch: no two neighbours share a weft
            for (int j = 0; j + 1 < opt.warps; ++j)
                for (int i = 0; i < opt.wefts; ++i)
                    EXPECT_FALSE(warp_height(y, j, i) < 0 && warp_height(y, j + 1, i) < 0);
        }
    }
}

TEST(Swatch, ParsesKindsAndRejectsBadOptions) {
    EXPECT_EQ(parse_swatch_kind("knit"), SwatchKind::Knit);
    EXPECT_EQ(parse_swatch_kind("plain"), SwatchKind::Plain);
    EXPECT_EQ(parse_swatch_kind("twill"), SwatchKind::Twill);
    EXPECT_EQ(parse_swatch_kind("satin"), SwatchKind::Satin);
    try {
        parse_swatch_kind("jersey");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(e.reason().find("'jersey'"), std::string::npos);
        EXPECT_NE(e.reason().find("knit, plain, twill or satin"), std::string::npos);
    }
    SwatchOptions opt;
    opt.spacing = 0.9f * default_swatch_spacing(SwatchKind::Plain, opt.yarn_radius);
    EXPECT_THROW(generate_swatch(SwatchKind::Plain, opt), InputError);  // would intersect
    opt = SwatchOptions();
    opt.yarn_radius = -1;
    EXPECT_THROW(generate_swatch(SwatchKind::Knit, opt), InputError);
    opt = SwatchOptions();
    opt.courses = 0;
    EXPECT_THROW(generate_swatch(SwatchKind::Knit, opt), InputError);
    opt = SwatchOptions();
    opt.twill_over = 0;
    EXPECT_THROW(generate_swatch(SwatchKind::Twill, opt), InputError);
    opt = SwatchOptions();
    opt.warps = 1;
    opt.wefts = 1;
    EXPECT_NO_THROW(validate_curves(generate_swatch(SwatchKind::Plain, opt), "one crossing"));
    // Each count alone is allowed, their product would be about 10^8 control points: refused
    // before anything is allocated.
    opt = SwatchOptions();
    opt.warps = opt.wefts = 5000;
    try {
        generate_swatch(SwatchKind::Plain, opt);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("warps x wefts 25000000 is more than"), std::string::npos) << e.what();
    }
    opt = SwatchOptions();
    opt.courses = opt.wales = 2000;
    EXPECT_THROW(generate_swatch(SwatchKind::Knit, opt), InputError);
}

}  // namespace
}  // namespace purl
