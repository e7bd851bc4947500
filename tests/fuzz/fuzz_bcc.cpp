// libFuzzer target: the BCC reader (read_bcc, then load_bcc's conversion to B-splines and
// validate_curves), fed through an in-memory file so the real path-based entry point runs,
// size checks and all, without touching the disk.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scene/bcc.h"
#include "scene/curves.h"
#include "scene/input_error.h"

namespace {

// One memfd for the whole run; each input replaces its contents.
int memory_file() {
    static const int fd = [] {
        const int f = memfd_create("fuzz.bcc", 0);
        if (f < 0) std::abort();
        return f;
    }();
    return fd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const int fd = memory_file();
    if (ftruncate(fd, 0) != 0) std::abort();
    for (size_t done = 0; done < size;) {
        const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) std::abort();
        done += static_cast<size_t>(n);
    }
    // Opening /proc/self/fd/N gives a fresh file position, like opening a real file.
    const std::string path = "/proc/self/fd/" + std::to_string(fd);
    purl::YarnCurves curves;
    try {
        curves = purl::load_bcc(path, 0.01f);
    } catch (const purl::InputError&) {
        return 0;  // bad input must end here, as a clear error; any other exception is a bug
    }
    // What load_bcc accepts must be renderable: a rejection here is a reader bug.
    try {
        purl::validate_curves(curves, path);
    } catch (const purl::InputError& e) {
        std::fprintf(stderr, "load_bcc accepted curves that validate_curves rejects: %s\n", e.what());
        std::abort();
    }
    return 0;
}
