// Image files through OpenImageIO: multilayer EXR as Blender reads it, sRGB PNG, and
// reading environment images. Files are written to a temporary name and renamed, so a
// failed write never replaces a good image with a truncated one.
#pragma once
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

// Channels are named "<layer>.<pass>.<channel>" (Blender's RenderResult.load_from_file).
void write_multilayer_exr(const std::string& path, const RenderImage& image, const std::string& layer);
// The Combined pass, sRGB-encoded, straight (unpremultiplied) alpha, 8 bits.
void write_png(const std::string& path, const RenderImage& image);
// Any image OIIO reads, as linear RGB floats. Throws InputError.
ImageRGB read_image_rgb(const std::string& path);

}  // namespace purl
