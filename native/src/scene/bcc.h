// BCC ("binary curve collection", Cem Yuksel's yarn-level cloth models): reader and writer.
//
// Layout (little-endian): a 64-byte header
//   char[3] "BCC" | uint8 0x44 (4-byte ints and floats) | char[2] type ("C0" uniform
//   Catmull-Rom, "PL" polyline, "BS" uniform cubic B-spline, "BZ" cubic Bezier) |
//   uint8 dimensions (3) | uint8 up axis (1 = Y, 2 = Z) | uint64 curves | uint64 points |
//   char[40] info
// then per curve an int32 n (negative = closed loop of |n| points) and |n| float3 points.
// The file size is exactly 64 + 4 * curves + 12 * points; the reader checks that before
// allocating anything. BCC has no radius: the loader takes one, in the file's units.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "math/spline_convert.h"
#include "scene/curves.h"

namespace purl {

struct BccHeader {
    CurveBasis basis = CurveBasis::BSpline;
    std::string type;           // the two type characters as stored, e.g. "C0"
    int up_axis = 2;            // 1 = Y-up, 2 = Z-up
    uint64_t curve_count = 0;
    uint64_t point_count = 0;
    std::string info;           // up to 40 characters, cut at the first NUL
};

// Curves as stored in the file: no basis change, no axis change.
struct BccCurves {
    BccHeader header;
    std::vector<Vec3> points;               // file units, file axes
    std::vector<uint32_t> curve_offsets{0};  // curve c owns points[offsets[c] .. offsets[c+1])
    std::vector<uint8_t> closed;            // per curve

    size_t curve_count() const { return closed.size(); }
};

// Reads and checks the 64-byte header and the exact file size. Throws InputError.
BccHeader read_bcc_header(const std::string& path);
// Reads the whole file in one go and checks every curve. Throws InputError naming the
// file, the byte offset or curve index, and the reason.
BccCurves read_bcc(const std::string& path);

// Loads a BCC file as renderable yarn centre-lines: exact conversion to B-spline segments,
// Y-up files turned Z-up by the rotation (x, y, z) -> (x, -z, y), every point given
// `radius` (file units, > 0). Curve ids are the curve indices in the file.
YarnCurves load_bcc(const std::string& path, float radius);

// The Y-up -> Z-up rotation (+90 degrees about X; determinant +1, so handedness is kept).
inline Vec3 bcc_y_up_to_z_up(Vec3 p) { return {p.x, -p.z, p.y}; }

// The curves as a "BS" file stores them, in file order: a chain as it is (a closed loop
// without its 3 wrapped points), a curve made of independent segments as one open 4-point
// curve per segment.
void for_each_bcc_curve(const YarnCurves& curves,
                        const std::function<void(const Vec4* points, size_t count, bool closed)>& visit);

// Writes curves as a Z-up "BS" file (for_each_bcc_curve; closed loops as a negative count).
// Radii are dropped (BCC has none). Throws InputError if the file cannot be written.
void write_bcc(const std::string& path, const YarnCurves& curves, const std::string& info = "");

}  // namespace purl
