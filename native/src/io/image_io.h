// Image files through OpenImageIO: multilayer EXR as Blender reads it, sRGB PNG, and
// reading environment images. Files are written to a temporary name and renamed, so a
// failed write never replaces a good image with a truncated one.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace purl {

struct ImagePass {
    std::string name;                        // "Combined", "Depth", ...
    std::vector<std::string> channel_names;  // "R","G","B","A" / "Z" / "X","Y","Z"
    std::vector<float> pixels;               // interleaved, rows top to bottom
    int channels() const { return static_cast<int>(channel_names.size()); }
};

struct RenderImage {
    int width = 0, height = 0;
    std::vector<ImagePass> passes;
    const ImagePass* find(const std::string& name) const;
};

struct ImageRGB {
    int width = 0, height = 0;
    std::vector<float> rgb;  // rows top to bottom
};

// Refuses, before any work, an output that could not be written afterwards: InputError naming
// the path, `option` (e.g. "-o") and the reason: a folder that does not exist or cannot be
// written, a path that is a folder, an extension other than .exr or .png (only .png when
// `png_only`).
void check_output_path(const std::string& path, const std::string& option, bool png_only = false);

// Writes `path` by calling `write` on a sibling temporary of the same extension, then renaming
// it into place: a failed write leaves the previous file and no temporary.
void write_file_atomically(const std::string& path, const std::function<void(const std::string&)>& write);
// For a signal handler (async-signal-safe): removes the temporary of the write in progress, if
// any, so that a process killed while writing leaves no partial file behind.
void discard_partial_output();

// Channels are named "<layer>.<pass>.<channel>" (Blender's RenderResult.load_from_file).
void write_multilayer_exr(const std::string& path, const RenderImage& image, const std::string& layer);
// The Combined pass, sRGB-encoded, straight (unpremultiplied) alpha, 8 bits.
void write_png(const std::string& path, const RenderImage& image);
// Linear RGB as a half-float, zip-compressed EXR: small enough for stored reference images.
void write_rgb_exr(const std::string& path, const ImageRGB& image);
// Any image OIIO reads, as linear RGB floats. Throws InputError.
ImageRGB read_image_rgb(const std::string& path);

}  // namespace purl
