// Helpers shared by the robustness suite: a scratch folder, raw BCC bytes, peak memory.
#pragma once
#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/input_error.h"

namespace purl::robustness {

namespace fs = std::filesystem;

// A folder of its own per test process, removed at the end.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& name)
        : path_(fs::temp_directory_path() / ("purl-robustness-" + name + "-" + std::to_string(getpid()))) {
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    std::string write(const std::string& name, const std::string& bytes) const {
        std::ofstream out(file(name), std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return file(name);
    }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

inline void put_u32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline void put_u64(std::string& s, uint64_t v) {
    put_u32(s, static_cast<uint32_t>(v));
    put_u32(s, static_cast<uint32_t>(v >> 32));
}
inline void put_f32(std::string& s, float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put_u32(s, bits);
}

// A 64-byte BCC header with the given counts, whatever the body holds.
inline std::string bcc_header(const char type[2], uint64_t curves, uint64_t points, uint8_t up = 2) {
    std::string h = "BCC";
    h.push_back(static_cast<char>(0x44));
    h.append(type, 2);
    h.push_back(3);
    h.push_back(static_cast<char>(up));
    put_u64(h, curves);
    put_u64(h, points);
    h.append(40, '\0');
    return h;
}

// A whole BCC file: one curve per entry, `closed` marking negative counts.
struct RawCurve {
    std::vector<float> xyz;
    bool closed = false;
};
inline std::string bcc_file(const char type[2], const std::vector<RawCurve>& curves) {
    std::string body;
    uint64_t points = 0;
    for (const RawCurve& c : curves) {
        const int32_t n = static_cast<int32_t>(c.xyz.size() / 3);
        put_u32(body, static_cast<uint32_t>(c.closed ? -n : n));
        for (float f : c.xyz) put_f32(body, f);
        points += static_cast<uint64_t>(n);
    }
    return bcc_header(type, curves.size(), points) + body;
}

// Peak resident memory of this process so far (Linux reports kilobytes).
inline size_t peak_resident_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<size_t>(usage.ru_maxrss) * 1024;
}

// Bytes this process has read through read() and friends so far (/proc/self/io "rchar"): how
// much of a file a reader looked at, counted rather than timed. 0 where /proc is missing.
inline uint64_t bytes_read() {
    std::ifstream io("/proc/self/io");
    std::string key;
    uint64_t value = 0;
    while (io >> key >> value)
        if (key == "rchar:") return value;
    return 0;
}

// The InputError's text from running `f`, or "" when nothing (or something else) was thrown.
template <class F>
std::string input_error_of(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace purl::robustness
