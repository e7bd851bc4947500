// Denoising with Intel Open Image Denoise (OIDN 2), loaded at run time.
//
// Debian 12 packages no OIDN; the PyPI wheel `pyoidn` ships libOpenImageDenoise.so.2 (CPU
// device) but no C headers. Purl therefore opens the library with dlopen and calls the few
// functions of OIDN's documented C API it needs through its own declarations (denoise.cpp), so
// Purl builds and runs without OIDN and only `--denoise` needs it. The library's own oneTBB
// (libtbb.so.12) is never loaded: Purl has already loaded Debian's libtbb.so.12, and the
// dynamic loader resolves OIDN's dependency to that copy by its soname. docs/denoising.md.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/image_io.h"

namespace purl {

// OIDN could not be found or loaded; what() says where Purl looked and how to install it.
class DenoiserUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

inline constexpr const char* kNoisyImagePass = "Noisy Image";  // Cycles' name for the input

struct DenoiseOptions {
    int threads = 0;        // 0: all cores
    // Denoise the albedo and normal guides first and then trust them as clean (OIDN's
    // recommended route when the guides carry noise of their own, as Purl's do at low spp).
    bool prefilter_guides = true;
};

class Denoiser {
public:
    // Opens OIDN once per process: $PURL_OIDN_LIBRARY when set (alone), else the library CMake
    // found at configure time (the installed pyoidn), then libOpenImageDenoise.so.2 on the
    // loader's path. Throws DenoiserUnavailable naming each place tried.
    static std::shared_ptr<const Denoiser> load();
    // The candidate paths load() tries, in order.
    static std::vector<std::string> library_candidates();
    // The first candidate that opens and has OIDN 2's functions (not cached).
    static std::shared_ptr<const Denoiser> load_from(const std::vector<std::string>& candidates);
    ~Denoiser();

    const std::string& library_path() const { return path_; }
    // Replaces the RGB of the Combined pass by OIDN's RT filter output (HDR, guided by the
    // Denoising Albedo and Denoising Normal passes when present; alpha is kept) and adds the
    // input as a "Noisy Image" pass. Throws std::runtime_error with OIDN's message on failure.
    void denoise(RenderImage& image, const DenoiseOptions& options) const;

    struct Api;

private:
    Denoiser(void* handle, std::string path, std::unique_ptr<Api> api);
    void* handle_;
    std::string path_;
    std::unique_ptr<Api> api_;
};

}  // namespace purl
