#include "fit/fit_target.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "base/input_error.h"
#include "scene/scene_json.h"

namespace purl {

namespace fs = std::filesystem;
using OIIO::ImageInput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

// Index of the channel called `suffix` (exactly, or ending in "." + suffix), -1 if none.
int find_channel(const ImageSpec& spec, const std::string& exact, const std::string& suffix) {
    for (int c = 0; c < spec.nchannels; ++c)
        if (spec.channel_name(c) == exact) return c;
    for (int c = 0; c < spec.nchannels; ++c) {
        const std::string name = spec.channel_name(c);
        if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
            return c;
    }
    return -1;
}

}  // namespace

void read_target_image(const std::string& path, int& width, int& height, std::vector<float>& rgb) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path, "", "no such file");
    if (!fs::is_regular_file(path, ec)) throw InputError(path, "", "not a regular file");
    auto in = ImageInput::open(path);
    if (!in) throw InputError(path, "", "cannot read image: " + OIIO::geterror());
    const ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw InputError(path, "", "image has no pixels");
    if (size_t(spec.width) * spec.height > (size_t(1) << 26))
        throw InputError(path, "", "image is too large for a fitting target");
    // Purl's and Blender's multilayer EXRs name channels "<layer>.Combined.R"; plain files "R".
    int channel[3];
    const char* names[3] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
        channel[k] = find_channel(spec, names[k], std::string("Combined.") + names[k]);
        if (channel[k] < 0) channel[k] = find_channel(spec, names[k], std::string(".") + names[k]);
        if (channel[k] < 0) channel[k] = std::min(k, spec.nchannels - 1);  // grey or unnamed channels
    }
    std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, all.data()))
        throw InputError(path, "", "cannot decode image: " + in->geterror());
    width = spec.width;
    height = spec.height;
    rgb.assign(size_t(width) * height * 3, 0.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(y) * width + x;
            for (int k = 0; k < 3; ++k) {
                const float v = all[i * spec.nchannels + channel[k]];
                if (!std::isfinite(v))
                    throw InputError(path, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")",
                                     "value is not finite; a target must hold finite radiance everywhere");
                rgb[i * 3 + k] = v;
            }
        }
}

void check_fit_target(const FitTarget& t) {
    const int w = t.scene.film.width, h = t.scene.film.height;
    if (t.width != w || t.height != h)
        throw InputError(t.name, "", "the target is " + std::to_string(t.width) + " x " + std::to_string(t.height) +
                                         " pixels but its scene renders " + std::to_string(w) + " x " +
                                         std::to_string(h) + "; render the target with the scene's film size");
    if (t.rgb.size() != size_t(w) * h * 3) throw InputError(t.name, "", "pixel data does not match the size");
    for (size_t i = 0; i < t.rgb.size(); ++i)
        if (!std::isfinite(t.rgb[i]))
            throw InputError(t.name, "pixel (" + std::to_string(i / 3 % w) + ", " + std::to_string(i / 3 / w) + ")",
                             "value is not finite");
    if (!t.weight.empty()) {
        if (t.weight.size() != size_t(w) * h) throw InputError(t.name, "mask", "does not match the target's size");
        double total = 0;
        for (float v : t.weight) {
            if (!std::isfinite(v) || v < 0) throw InputError(t.name, "mask", "weights must be finite and >= 0");
            total += v;
        }
        if (total <= 0) throw InputError(t.name, "mask", "selects no pixels");
    }
    bool has_bysdf = false;
    for (const YarnSetDesc& y : t.scene.yarns) has_bysdf = has_bysdf || y.material.model == MaterialModel::Bysdf;
    if (!has_bysdf) throw InputError(t.scene.source, "yarns", "no yarn with a bysdf material to fit");
}

FitTarget load_fit_target(const std::string& scene_path, const std::string& image_path, const std::string& mask_path) {
    FitTarget t;
    t.name = image_path;
    t.scene = load_scene_file(scene_path);
    read_target_image(image_path, t.width, t.height, t.rgb);
    if (!mask_path.empty()) {
        int mw = 0, mh = 0;
        std::vector<float> mask_rgb;
        read_target_image(mask_path, mw, mh, mask_rgb);
        if (mw != t.width || mh != t.height)
            throw InputError(mask_path, "", "the mask is " + std::to_string(mw) + " x " + std::to_string(mh) +
                                                " pixels, the target " + std::to_string(t.width) + " x " +
                                                std::to_string(t.height));
        t.weight.resize(size_t(mw) * mh);
        for (size_t i = 0; i < t.weight.size(); ++i) t.weight[i] = std::clamp(mask_rgb[i * 3], 0.0f, 1.0f);
    }
    check_fit_target(t);
    return t;
}

}  // namespace purl
