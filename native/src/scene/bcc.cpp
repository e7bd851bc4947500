#include "scene/bcc.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "base/input_error.h"

namespace purl {
namespace {

constexpr uint64_t kHeaderBytes = 64;
constexpr uint64_t kCountBytes = 4;   // int32 per curve
constexpr uint64_t kPointBytes = 12;  // float3 per point
// At most 2^28 points (a 3 GB file): converted curves index control points with uint32 and
// Catmull-Rom/Bezier become 4 points per segment, so this keeps every index below 2^31.
constexpr uint64_t kMaxPoints = uint64_t(1) << 28;
// Points are read in batches of this many, so memory follows the data read and checked,
// never what a header claims (a sparse file of several GB costs one batch).
constexpr uint64_t kBatchPoints = uint64_t(1) << 16;

// Little-endian field readers, independent of the host's byte order.
uint32_t read_u32(const unsigned char* b) {
    return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
}
uint64_t read_u64(const unsigned char* b) { return uint64_t(read_u32(b)) | uint64_t(read_u32(b + 4)) << 32; }
float read_f32(const unsigned char* b) {
    const uint32_t bits = read_u32(b);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}
void put_u32(std::string& out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_u64(std::string& out, uint64_t v) {
    put_u32(out, static_cast<uint32_t>(v));
    put_u32(out, static_cast<uint32_t>(v >> 32));
}
void put_f32(std::string& out, float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put_u32(out, bits);
}

// Places in error messages are byte offsets from the start of the file.
std::string at_byte(uint64_t offset) { return "byte " + std::to_string(offset); }

bool parse_basis(const char t[2], CurveBasis& basis) {
    const std::string s(t, 2);
    if (s == "C0") basis = CurveBasis::CatmullRom;
    else if (s == "PL") basis = CurveBasis::Polyline;
    else if (s == "BS") basis = CurveBasis::BSpline;
    else if (s == "BZ") basis = CurveBasis::Bezier;
    else return false;
    return true;
}

// Header bytes shown in messages: printable ASCII as is, anything else as \xNN.
std::string printable(const unsigned char* b, size_t n) {
    std::string s;
    for (size_t i = 0; i < n; ++i) {
        if (b[i] >= 32 && b[i] < 127) s.push_back(static_cast<char>(b[i]));
        else s += "\\x" + std::string(1, "0123456789abcdef"[b[i] >> 4]) + "0123456789abcdef"[b[i] & 15];
    }
    return s;
}

// Checks the header fields and that the file size matches its counts exactly, so no
// allocation below can exceed what the file holds.
BccHeader parse_header(const std::string& path, const unsigned char* h, uint64_t file_size) {
    if (std::memcmp(h, "BCC", 3) != 0)
        throw InputError(path, at_byte(0), "not a BCC file: signature is '" + printable(h, 3) + "', expected 'BCC'");
    if (h[3] != 0x44)
        throw InputError(path, at_byte(3), "unsupported number size byte " + printable(h + 3, 1) +
                                               "; only 0x44 (4-byte integers and floats) is supported");
    BccHeader header;
    if (!parse_basis(reinterpret_cast<const char*>(h + 4), header.basis))
        throw InputError(path, at_byte(4), "unknown curve type '" + printable(h + 4, 2) +
                                               "'; expected C0, PL, BS or BZ");
    header.type.assign(reinterpret_cast<const char*>(h + 4), 2);
    if (h[6] != 3)
        throw InputError(path, at_byte(6), "curves have " + std::to_string(h[6]) +
                                               " dimensions; only 3 is supported");
    if (h[7] != 1 && h[7] != 2)
        throw InputError(path, at_byte(7), "up axis is " + std::to_string(h[7]) +
                                               "; expected 1 (Y-up) or 2 (Z-up)");
    header.up_axis = h[7];
    // The info field is free text, often unterminated garbage in real files: stop at a NUL.
    header.curve_count = read_u64(h + 8);
    header.point_count = read_u64(h + 16);
    const char* info = reinterpret_cast<const char*>(h + 24);
    header.info.assign(info, strnlen(info, 40));

    const uint64_t body = file_size - kHeaderBytes;
    // Each count alone must fit in the file; this also keeps the size arithmetic below
    // from overflowing, whatever the header says.
    auto too_many = [&](uint64_t count, uint64_t bytes_each, const char* what, uint64_t offset) {
        if (count > body / bytes_each)
            throw InputError(path, at_byte(offset),
                             "header declares " + std::to_string(count) + " " + what + ", more than the " +
                                 std::to_string(body) + " bytes after the header can hold (truncated file or corrupt count)");
    };
    too_many(header.curve_count, kCountBytes, "curves", 8);
    too_many(header.point_count, kPointBytes, "points", 16);
    // Both counts are now bounded by the file size, so this sum cannot overflow.
    const uint64_t expected =
        kHeaderBytes + kCountBytes * header.curve_count + kPointBytes * header.point_count;
    if (expected != file_size)
        throw InputError(path, at_byte(std::min(expected, file_size)),
                         "file has " + std::to_string(file_size) + " bytes but the header's " +
                             std::to_string(header.curve_count) + " curves and " +
                             std::to_string(header.point_count) + " points need " +
                             std::to_string(expected) +
                             (expected > file_size ? " (truncated)" : " (extra bytes at the end)"));
    if (header.curve_count == 0) throw InputError(path, at_byte(8), "file holds no curves");
    if (header.point_count > kMaxPoints)
        throw InputError(path, at_byte(16), "header declares " + std::to_string(header.point_count) +
                                                " points; at most " + std::to_string(kMaxPoints) +
                                                " (2^28) per file are supported");
    return header;
}

// Opens at the end to learn the size, then rewinds; the size decides what may be allocated.
std::ifstream open_for_reading(const std::string& path, uint64_t& size) {
    // A FIFO would block and a device has no size to check: only regular files.
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw InputError(path, "", "cannot open file");
    if (!std::filesystem::is_regular_file(status)) throw InputError(path, "", "not a regular file");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw InputError(path, "", "cannot open file");
    const std::streamoff end = in.tellg();
    if (end < 0) throw InputError(path, "", "cannot determine the file size");
    size = static_cast<uint64_t>(end);
    if (size < kHeaderBytes)
        throw InputError(path, at_byte(size), "file has " + std::to_string(size) +
                                                  " bytes, fewer than the 64-byte BCC header");
    in.seekg(0);
    return in;
}

}  // namespace

BccHeader read_bcc_header(const std::string& path) {
    uint64_t size = 0;
    std::ifstream in = open_for_reading(path, size);
    unsigned char h[kHeaderBytes];
    if (!in.read(reinterpret_cast<char*>(h), kHeaderBytes)) throw InputError(path, at_byte(0), "cannot read the header");
    return parse_header(path, h, size);
}

BccCurves read_bcc(const std::string& path) {
    uint64_t size = 0;
    std::ifstream in = open_for_reading(path, size);
    unsigned char h[kHeaderBytes];
    if (!in.read(reinterpret_cast<char*>(h), kHeaderBytes)) throw InputError(path, at_byte(0), "cannot read the header");
    BccCurves out;
    out.header = parse_header(path, h, size);  // size now matches the counts exactly

    const BccHeader& hd = out.header;
    // Reserve only what a small file would need; larger files grow as their data checks out.
    out.points.reserve(std::min(hd.point_count, kBatchPoints));
    out.curve_offsets.reserve(std::min(hd.curve_count, kBatchPoints) + 1);
    out.closed.reserve(std::min(hd.curve_count, kBatchPoints));
    std::vector<unsigned char> batch;
    uint64_t pos = 0, used = 0;  // byte position after the header, points consumed
    auto read_bytes = [&](unsigned char* dst, uint64_t n) {
        if (!in.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n)))
            throw InputError(path, at_byte(kHeaderBytes + pos), "cannot read the curve data (file changed while reading?)");
    };
    // Counts are checked against what remains before any point of the curve is read.
    for (uint64_t c = 0; c < hd.curve_count; ++c) {
        const std::string place = "curve " + std::to_string(c) + " (" + at_byte(kHeaderBytes + pos) + ")";
        if (pos + kCountBytes > size - kHeaderBytes)
            throw InputError(path, place, "curve data ends before the header's " +
                                              std::to_string(hd.curve_count) + " curves");
        unsigned char count[kCountBytes];
        read_bytes(count, kCountBytes);
        // Widened before negating, so INT32_MIN cannot overflow.
        const int64_t signed_n = static_cast<int32_t>(read_u32(count));
        pos += kCountBytes;
        const bool closed = signed_n < 0;
        const uint64_t n = static_cast<uint64_t>(closed ? -signed_n : signed_n);
        if (n > hd.point_count - used)
            throw InputError(path, place, "declares " + std::to_string(n) + " points but only " +
                                              std::to_string(hd.point_count - used) + " of the header's " +
                                              std::to_string(hd.point_count) + " remain");
        if (!valid_point_count(hd.basis, n, closed))
            throw InputError(path, place,
                             std::string(closed ? "closed " : "open ") + curve_basis_name(hd.basis) +
                                 " curve cannot have " + std::to_string(n) + " points (needs at least " +
                                 std::to_string(min_points(hd.basis, closed)) +
                                 (hd.basis == CurveBasis::Bezier ? (closed ? ", a multiple of 3" : ", 3k+1") : "") + ")");
        for (uint64_t i = 0; i < n;) {
            const uint64_t count_now = std::min(n - i, kBatchPoints);
            batch.resize(count_now * kPointBytes);
            read_bytes(batch.data(), batch.size());
            for (uint64_t k = 0; k < count_now; ++k, ++i, pos += kPointBytes) {
                const unsigned char* b = &batch[k * kPointBytes];
                const Vec3 p(read_f32(b), read_f32(b + 4), read_f32(b + 8));
                if (!is_finite(p))
                    throw InputError(path, "curve " + std::to_string(c) + ", point " + std::to_string(i) + " (" +
                                               at_byte(kHeaderBytes + pos) + ")",
                                     "coordinate is not finite");
                out.points.push_back(p);
            }
        }
        used += n;
        out.curve_offsets.push_back(static_cast<uint32_t>(used));
        out.closed.push_back(closed ? 1 : 0);
    }
    if (used != hd.point_count)
        throw InputError(path, at_byte(kHeaderBytes + pos),
                         "curves hold " + std::to_string(used) + " points but the header declares " +
                             std::to_string(hd.point_count));
    return out;
}

YarnCurves load_bcc(const std::string& path, float radius) {
    if (!(radius > 0.0f) || !std::isfinite(radius))
        throw InputError(path, "radius", "yarn radius must be positive and finite, got " + std::to_string(radius));
    const BccCurves file = read_bcc(path);
    const bool y_up = file.header.up_axis == 1;
    YarnCurves curves;
    curves.control_points.reserve(file.points.size() + 3 * file.curve_count());
    std::vector<Vec4> points;  // one curve at a time, reused
    for (size_t c = 0; c < file.curve_count(); ++c) {
        const uint32_t begin = file.curve_offsets[c], end = file.curve_offsets[c + 1];
        points.clear();
        for (uint32_t i = begin; i < end; ++i)
            points.emplace_back(y_up ? bcc_y_up_to_z_up(file.points[i]) : file.points[i], radius);
        const BSplineSegments seg =
            to_bspline_segments(file.header.basis, points.data(), points.size(), file.closed[c] != 0);
        // Finite points near the float limit can overflow in the basis change (found by fuzzing).
        for (const Vec4& p : seg.points)
            if (!is_finite(p.xyz()))
                throw InputError(path, "curve " + std::to_string(c),
                                 "coordinates too large: converting them to B-spline control points overflows");
        curves.add(seg, file.closed[c] != 0, static_cast<int32_t>(c));
    }
    // Every point the same: nothing to render at any radius (validate_curves would refuse it
    // later, blaming no file place; found by fuzzing).
    const std::vector<Vec4>& cp = curves.control_points;
    const auto same_place = [&](const Vec4& p) { return p.x == cp[0].x && p.y == cp[0].y && p.z == cp[0].z; };
    if (!cp.empty() && std::all_of(cp.begin(), cp.end(), same_place))
        throw InputError(path, file.curve_count() == 1 ? "curve 0" : "every curve",
                         "is collapsed to one point (all its points are equal): nothing to render");
    return curves;
}

void for_each_bcc_curve(const YarnCurves& curves,
                        const std::function<void(const Vec4* points, size_t count, bool closed)>& visit) {
    for (size_t c = 0; c < curves.curve_count(); ++c) {
        const uint32_t begin = curves.curve_offsets[c], end = curves.curve_offsets[c + 1];
        const uint32_t s0 = curves.segment_offsets[c], s1 = curves.segment_offsets[c + 1];
        // A chain has n - 3 segments starting at consecutive points.
        bool chain = (end - begin) == (s1 - s0) + 3;
        for (uint32_t s = s0; chain && s < s1; ++s) chain = curves.segment_first[s] == begin + (s - s0);
        const Vec4* p = &curves.control_points[begin];
        if (chain) {
            const size_t n = end - begin;
            // A closed chain ends with its first three points repeated; BCC stores them once.
            bool wrapped = curves.closed[c] && n >= 6;
            for (size_t i = 0; wrapped && i < 3; ++i)
                wrapped = std::memcmp(&p[n - 3 + i], &p[i], sizeof(Vec4)) == 0;
            visit(p, wrapped ? n - 3 : n, wrapped);
        } else {
            for (uint32_t s = s0; s < s1; ++s) visit(&curves.control_points[curves.segment_first[s]], 4, false);
        }
    }
}

void write_bcc(const std::string& path, const YarnCurves& curves, const std::string& info) {
    // Built in memory first: the header needs the counts, and the file is written in one go.
    std::string body;
    uint64_t curve_count = 0, point_count = 0;
    for_each_bcc_curve(curves, [&](const Vec4* p, size_t n, bool closed) {
        put_u32(body, static_cast<uint32_t>(closed ? -static_cast<int32_t>(n) : static_cast<int32_t>(n)));
        for (size_t i = 0; i < n; ++i) {
            put_f32(body, p[i].x);
            put_f32(body, p[i].y);
            put_f32(body, p[i].z);
        }
        ++curve_count;
        point_count += n;
    });
    std::string file;
    file.reserve(kHeaderBytes + body.size());
    file += "BCC";
    file.push_back(static_cast<char>(0x44));
    file += "BS";
    file.push_back(3);
    file.push_back(2);  // Z-up
    put_u64(file, curve_count);
    put_u64(file, point_count);
    std::string info40 = info.substr(0, 40);
    info40.resize(40, '\0');
    file += info40;
    file += body;

    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, "", "cannot open file for writing");
    out.write(file.data(), static_cast<std::streamsize>(file.size()));
    if (!out) throw InputError(path, "", "write failed");
}

}  // namespace purl
