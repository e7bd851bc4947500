#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>

#include "base/input_error.h"
#include "math/vec.h"

namespace purl {

namespace fs = std::filesystem;
using namespace OIIO;

const ImagePass* RenderImage::find(const std::string& name) const {
    for (const ImagePass& p : passes)
        if (p.name == name) return &p;
    return nullptr;
}

namespace {

// A sibling temporary path with the same extension, so OIIO picks the same format. The
// process id and a counter keep two writes of the same output (two renders at once, in
// one process or two) from sharing a temporary; the last rename wins with a whole file.
std::string temporary_path(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    const fs::path p(path);
    const std::string unique = std::to_string(getpid()) + "-" + std::to_string(counter++);
    return (p.parent_path() / (".tmp-" + p.stem().string() + "-" + unique + p.extension().string())).string();
}

// The temporary being written, for discard_partial_output (one at a time: the CLI writes its
// images one after the other; a second concurrent write is not registered).
char g_partial_path[4096];
std::atomic<bool> g_partial_set{false};

bool register_partial(const std::string& tmp) {
    bool expected = false;
    if (tmp.size() >= sizeof(g_partial_path) || !g_partial_set.compare_exchange_strong(expected, true)) return false;
    std::memcpy(g_partial_path, tmp.c_str(), tmp.size() + 1);
    return true;
}

}  // namespace

void discard_partial_output() {
    if (g_partial_set.load()) unlink(g_partial_path);
}

void write_file_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    const std::string tmp = temporary_path(path);
    const bool registered = register_partial(tmp);
    try {
        write(tmp);
        fs::rename(tmp, path);
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        if (registered) g_partial_set = false;
        throw;
    }
    if (registered) g_partial_set = false;
}

void check_output_path(const std::string& path, const std::string& option, bool png_only) {
    if (path.find('\0') != std::string::npos)
        throw InputError(path.c_str(), option, "contains a NUL character; a file name cannot");
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError(path, option, "is a folder, not a file name");
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (png_only && ext != ".png") throw InputError(path, option, "must end in .png (an sRGB PNG is written there)");
    if (ext != ".exr" && ext != ".png") throw InputError(path, option, "must end in .exr or .png");
    const fs::path parent = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
    if (!fs::exists(parent, ec)) throw InputError(path, option, "folder " + parent.string() + " does not exist");
    if (!fs::is_directory(parent, ec)) throw InputError(path, option, parent.string() + " is not a folder");
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw InputError(path, option, "exists and is not a regular file");
    // The write goes through a temporary beside the output: make one now (permissions,
    // read-only or special file systems, quotas on inodes), as root too, where access() says yes.
    const std::string probe = temporary_path(path);
    const int fd = open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0)
        throw InputError(path, option, "cannot create a file in " + parent.string() + ": " + std::strerror(errno));
    close(fd);
    unlink(probe.c_str());
}

void write_multilayer_exr(const std::string& path, const RenderImage& image, const std::string& layer) {
    std::vector<std::string> names;
    for (const ImagePass& pass : image.passes)
        for (const std::string& c : pass.channel_names) names.push_back(layer + "." + pass.name + "." + c);
    const int nchannels = static_cast<int>(names.size());
    ImageSpec spec(image.width, image.height, nchannels, TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = -1;  // Blender reads channels by name; no OIIO alpha handling
    spec.z_channel = -1;
    spec.attribute("compression", "zip");

    // Interleave all passes into one scanline buffer.
    std::vector<float> data(size_t(image.width) * image.height * nchannels);
    int offset = 0;
    for (const ImagePass& pass : image.passes) {
        const int pc = pass.channels();
        for (size_t i = 0; i < size_t(image.width) * image.height; ++i)
            for (int c = 0; c < pc; ++c) data[i * nchannels + offset + c] = pass.pixels[i * pc + c];
        offset += pc;
    }
    write_file_atomically(path, [&](const std::string& tmp) {
        auto out = ImageOutput::create(tmp);
        if (!out) throw std::runtime_error(path + ": cannot create an EXR writer: " + OIIO::geterror());
        if (!out->open(tmp, spec) || !out->write_image(TypeDesc::FLOAT, data.data()) || !out->close())
            throw std::runtime_error(path + ": cannot write: " + out->geterror());
    });
}

void write_png(const std::string& path, const RenderImage& image) {
    const ImagePass* combined = image.find("Combined");
    if (!combined) throw std::runtime_error(path + ": no Combined pass to write");
    std::vector<unsigned char> bytes(size_t(image.width) * image.height * 4);
    for (size_t i = 0; i < size_t(image.width) * image.height; ++i) {
        const float* px = &combined->pixels[i * 4];
        const float alpha = std::min(1.0f, std::max(0.0f, px[3]));
        for (int c = 0; c < 3; ++c) {
            const float straight = alpha > 0 ? px[c] / alpha : 0.0f;
            bytes[i * 4 + c] = static_cast<unsigned char>(std::lround(255.0f * std::min(1.0f, srgb_encode(straight))));
        }
        bytes[i * 4 + 3] = static_cast<unsigned char>(std::lround(255.0f * alpha));
    }
    ImageSpec spec(image.width, image.height, 4, TypeDesc::UINT8);
    write_file_atomically(path, [&](const std::string& tmp) {
        auto out = ImageOutput::create(tmp);
        if (!out) throw std::runtime_error(path + ": cannot create a PNG writer: " + OIIO::geterror());
        if (!out->open(tmp, spec) || !out->write_image(TypeDesc::UINT8, bytes.data()) || !out->close())
            throw std::runtime_error(path + ": cannot write: " + out->geterror());
    });
}

void write_rgb_exr(const std::string& path, const ImageRGB& image) {
    ImageSpec spec(image.width, image.height, 3, TypeDesc::HALF);
    spec.attribute("compression", "zip");
    write_file_atomically(path, [&](const std::string& tmp) {
        auto out = ImageOutput::create(tmp);
        if (!out) throw std::runtime_error(path + ": cannot create an EXR writer: " + OIIO::geterror());
        if (!out->open(tmp, spec) || !out->write_image(TypeDesc::FLOAT, image.rgb.data()) || !out->close())
            throw std::runtime_error(path + ": cannot write: " + out->geterror());
    });
}

ImageRGB read_image_rgb(const std::string& path) {
    // A FIFO or device could block or never end: only regular files.
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) throw InputError(path, "", "not a regular file");
    auto in = ImageInput::open(path);
    if (!in) throw InputError(path, "", "cannot read image: " + OIIO::geterror());
    const ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw InputError(path, "", "image has no pixels");
    if (size_t(spec.width) * spec.height > (size_t(1) << 28))
        throw InputError(path, "", "image is too large (" + std::to_string(spec.width) + " x " +
                                       std::to_string(spec.height) + ")");
    // Only the channels kept are decoded: a file declaring thousands of channels must not
    // make this allocate for all of them.
    const int kept = std::min(spec.nchannels, 3);
    std::vector<float> all(size_t(spec.width) * spec.height * kept);
    if (!in->read_image(0, 0, 0, kept, TypeDesc::FLOAT, all.data()))
        throw InputError(path, "", "cannot decode image: " + in->geterror());
    ImageRGB image;
    image.width = spec.width;
    image.height = spec.height;
    image.rgb.resize(size_t(spec.width) * spec.height * 3);
    for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = all[i * kept + std::min(c, kept - 1)];
            if (!std::isfinite(v)) throw InputError(path, "pixel " + std::to_string(i), "value is not finite");
            image.rgb[i * 3 + c] = v;
        }
    return image;
}

}  // namespace purl
