#include "render/denoise.h"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <mutex>

#include "render/film.h"

#ifndef PURL_OIDN_LIBRARY_DEFAULT
#define PURL_OIDN_LIBRARY_DEFAULT ""
#endif

namespace purl {

namespace {

// OIDN 2's C API as its documentation describes it: opaque handles, enums passed as int.
using OidnDevice = void*;
using OidnFilter = void*;
constexpr int kOidnDeviceCpu = 1;
constexpr int kOidnFormatFloat3 = 3;
constexpr int kOidnErrorNone = 0;
constexpr const char* kSystemLibrary = "libOpenImageDenoise.so.2";

}  // namespace

struct Denoiser::Api {
    OidnDevice (*new_device)(int type);
    void (*set_device_int)(OidnDevice, const char* name, int value);
    void (*commit_device)(OidnDevice);
    int (*get_device_error)(OidnDevice, const char** message);
    void (*release_device)(OidnDevice);
    OidnFilter (*new_filter)(OidnDevice, const char* type);
    void (*set_shared_filter_image)(OidnFilter, const char* name, void* pointer, int format, size_t width,
                                    size_t height, size_t byte_offset, size_t pixel_stride, size_t row_stride);
    void (*set_filter_bool)(OidnFilter, const char* name, bool value);
    void (*commit_filter)(OidnFilter);
    void (*execute_filter)(OidnFilter);
    void (*release_filter)(OidnFilter);
};

namespace {

template <class Function>
void bind(void* handle, const char* name, Function& out) {
    void* symbol = dlsym(handle, name);
    if (!symbol) throw DenoiserUnavailable(std::string("the library has no ") + name + " (not OIDN 2?)");
    out = reinterpret_cast<Function>(symbol);
}

// OIDN 2.5 as pyoidn builds it frees some of its memory with glibc's free; in a process whose
// malloc is another allocator (Blender links jemalloc) that aborts the process ("free(): invalid
// pointer", measured with LD_PRELOAD=libjemalloc.so.2). Refused up front instead: an allocator
// that replaces malloc for the whole process exports its own API, which is looked for here.
void check_allocator() {
    for (const char* api : {"mallctl", "je_mallctl", "tc_malloc", "mi_malloc", "__asan_init"}) {
        void* symbol = dlsym(RTLD_DEFAULT, api);
        if (!symbol) continue;
        Dl_info info{};
        const std::string provider = dladdr(symbol, &info) && info.dli_fname ? info.dli_fname : api;
        throw DenoiserUnavailable(
            "Open Image Denoise cannot run in this process: malloc is replaced by " + provider + " (" + api +
            "; e.g. Blender's jemalloc), and the OIDN library frees with glibc's, which would crash it. "
            "Denoise in a separate process (the Blender add-on does).");
    }
}

std::unique_ptr<Denoiser::Api> bind_api(void* handle) {
    auto api = std::make_unique<Denoiser::Api>();
    bind(handle, "oidnNewDevice", api->new_device);
    bind(handle, "oidnSetDeviceInt", api->set_device_int);
    bind(handle, "oidnCommitDevice", api->commit_device);
    bind(handle, "oidnGetDeviceError", api->get_device_error);
    bind(handle, "oidnReleaseDevice", api->release_device);
    bind(handle, "oidnNewFilter", api->new_filter);
    bind(handle, "oidnSetSharedFilterImage", api->set_shared_filter_image);
    bind(handle, "oidnSetFilterBool", api->set_filter_bool);
    bind(handle, "oidnCommitFilter", api->commit_filter);
    bind(handle, "oidnExecuteFilter", api->execute_filter);
    bind(handle, "oidnReleaseFilter", api->release_filter);
    return api;
}

// A three-float image OIDN reads or writes in place: base pointer and strides in bytes.
struct Plane {
    float* data = nullptr;
    size_t pixel_stride = 0;
};

Plane plane_of(ImagePass& pass) {
    return {pass.pixels.data(), sizeof(float) * size_t(pass.channels())};
}

ImagePass* find_pass(RenderImage& image, const char* name, int min_channels) {
    for (ImagePass& p : image.passes)
        if (p.name == name && p.channels() >= min_channels && p.pixels.size() >= size_t(image.width) * image.height * 3)
            return &p;
    return nullptr;
}

// One OIDN device for one denoise call, released however the call ends.
class Session {
public:
    Session(const Denoiser::Api& api, const std::string& path, int threads) : api_(api), path_(path) {
        device_ = api_.new_device(kOidnDeviceCpu);
        if (!device_) throw std::runtime_error("Open Image Denoise (" + path_ + "): no CPU device");
        if (threads > 0) api_.set_device_int(device_, "numThreads", threads);
        api_.commit_device(device_);
        check("creating the CPU device");
    }
    ~Session() {
        if (device_) api_.release_device(device_);
    }
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Runs the RT filter: `inputs` by name ("color", "albedo", "normal"), result into `output`.
    void run(const std::vector<std::pair<const char*, Plane>>& inputs, Plane output, size_t width, size_t height,
             bool hdr, bool clean_guides) {
        OidnFilter filter = api_.new_filter(device_, "RT");
        if (!filter) check("creating the RT filter");
        struct Release {
            const Denoiser::Api& api;
            OidnFilter filter;
            ~Release() { api.release_filter(filter); }
        } release{api_, filter};
        for (const auto& [name, plane] : inputs)
            api_.set_shared_filter_image(filter, name, plane.data, kOidnFormatFloat3, width, height, 0, plane.pixel_stride, 0);
        api_.set_shared_filter_image(filter, "output", output.data, kOidnFormatFloat3, width, height, 0,
                                     output.pixel_stride, 0);
        api_.set_filter_bool(filter, "hdr", hdr);
        if (clean_guides) api_.set_filter_bool(filter, "cleanAux", true);
        api_.commit_filter(filter);
        api_.execute_filter(filter);
        check(std::string("denoising ") + inputs.front().first);
    }

private:
    void check(const std::string& doing) {
        const char* message = nullptr;
        if (api_.get_device_error(device_, &message) != kOidnErrorNone)
            throw std::runtime_error("Open Image Denoise (" + path_ + "), " + doing + ": " +
                                     (message ? message : "unknown error"));
    }
    const Denoiser::Api& api_;
    std::string path_;
    OidnDevice device_ = nullptr;
};

}  // namespace

std::vector<std::string> Denoiser::library_candidates() {
    // A path the user names is used alone: a wrong one is reported, not quietly replaced.
    if (const char* env = std::getenv("PURL_OIDN_LIBRARY"); env && *env) return {env};
    std::vector<std::string> paths;
    if (std::strlen(PURL_OIDN_LIBRARY_DEFAULT)) paths.push_back(PURL_OIDN_LIBRARY_DEFAULT);
    paths.push_back(kSystemLibrary);
    return paths;
}

std::shared_ptr<const Denoiser> Denoiser::load() {
    // Loaded once per process; a failed attempt is retried (the user may install OIDN meanwhile).
    static std::mutex mutex;
    static std::shared_ptr<const Denoiser> loaded;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!loaded) loaded = load_from(library_candidates());
    return loaded;
}

std::shared_ptr<const Denoiser> Denoiser::load_from(const std::vector<std::string>& candidates) {
    std::string tried;
    for (const std::string& path : candidates) {
        dlerror();
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();
            tried += "\n  " + path + ": " + (why ? why : "cannot be opened");
            continue;
        }
        std::unique_ptr<Api> api;
        try {
            api = bind_api(handle);
        } catch (const DenoiserUnavailable& e) {
            dlclose(handle);
            tried += "\n  " + path + ": " + e.what();
            continue;
        }
        try {
            check_allocator();
        } catch (const DenoiserUnavailable&) {
            dlclose(handle);
            throw;
        }
        return std::shared_ptr<const Denoiser>(new Denoiser(handle, path, std::move(api)));
    }
    throw DenoiserUnavailable(
        "denoising needs Intel Open Image Denoise 2, which was not found. Install it with "
        "`python3 -m pip install pyoidn` (scripts/setup.sh does) or point PURL_OIDN_LIBRARY at "
        "libOpenImageDenoise.so.2. Tried:" + tried);
}

Denoiser::Denoiser(void* handle, std::string path, std::unique_ptr<Api> api)
    : handle_(handle), path_(std::move(path)), api_(std::move(api)) {}

// The library stays loaded: OIDN's worker threads may outlive the last call briefly, and
// unloading code they run would crash the process.
Denoiser::~Denoiser() = default;

void Denoiser::denoise(RenderImage& image, const DenoiseOptions& options) const {
    ImagePass* combined = find_pass(image, "Combined", 3);
    if (!combined) throw std::runtime_error("denoise: the image has no Combined pass");
    const size_t width = size_t(image.width), height = size_t(image.height), n = width * height;
    ImagePass noisy = *combined;
    noisy.name = kNoisyImagePass;

    ImagePass* albedo = find_pass(image, kDenoisingAlbedoPass, 3);
    ImagePass* normal = find_pass(image, kDenoisingNormalPass, 3);
    if (!albedo) normal = nullptr;  // OIDN takes a normal only together with an albedo
    Session session(*api_, path_, options.threads);
    std::vector<std::pair<const char*, Plane>> inputs = {{"color", plane_of(noisy)}};
    // Prefiltered guides go into their own buffers: the passes keep what the render wrote.
    std::vector<float> clean[2];
    const bool prefilter = options.prefilter_guides && albedo;
    const std::pair<const char*, ImagePass*> guides[2] = {{"albedo", albedo}, {"normal", normal}};
    for (int g = 0; g < 2; ++g) {
        const auto [name, pass] = guides[g];
        if (!pass) continue;
        Plane plane = plane_of(*pass);
        if (prefilter) {
            clean[g].resize(n * 3);
            const Plane out{clean[g].data(), 3 * sizeof(float)};
            session.run({{name, plane}}, out, width, height, false, false);
            plane = out;
        }
        inputs.push_back({name, plane});
    }
    std::vector<float> output(n * 3);
    session.run(inputs, {output.data(), 3 * sizeof(float)}, width, height, true, prefilter);
    const int stride = combined->channels();
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) combined->pixels[i * stride + c] = output[3 * i + c];
    image.passes.push_back(std::move(noisy));
}

}  // namespace purl
