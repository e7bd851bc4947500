#include "render/film.h"

namespace purl {

RenderImage Film::to_image() const {
    RenderImage image;
    image.width = width_;
    image.height = height_;
    const size_t n = pixels_.size();
    ImagePass combined{"Combined", {"R", "G", "B", "A"}, std::vector<float>(n * 4)};
    ImagePass depth{"Depth", {"Z"}, std::vector<float>(n)};
    ImagePass normal{"Normal", {"X", "Y", "Z"}, std::vector<float>(n * 3)};
    ImagePass yarn_id{"YarnID", {"X"}, std::vector<float>(n)};
    ImagePass ply_index{"PlyIndex", {"X"}, std::vector<float>(n)};
    ImagePass ply_uv{"PlyUV", {"U", "V"}, std::vector<float>(n * 2)};
    ImagePass albedo{kDenoisingAlbedoPass, {"R", "G", "B"}, std::vector<float>(n * 3)};
    ImagePass denoising_normal{kDenoisingNormalPass, {"X", "Y", "Z"}, std::vector<float>(n * 3)};
    for (size_t i = 0; i < n; ++i) {
        const PixelResult& p = pixels_[i];
        combined.pixels[4 * i] = p.color.x;
        combined.pixels[4 * i + 1] = p.color.y;
        combined.pixels[4 * i + 2] = p.color.z;
        combined.pixels[4 * i + 3] = p.alpha;
        depth.pixels[i] = p.depth;
        normal.pixels[3 * i] = p.normal.x;
        normal.pixels[3 * i + 1] = p.normal.y;
        normal.pixels[3 * i + 2] = p.normal.z;
        yarn_id.pixels[i] = p.yarn_id;
        ply_index.pixels[i] = p.ply_index;
        ply_uv.pixels[2 * i] = p.u_ply;
        ply_uv.pixels[2 * i + 1] = p.v_ply;
        for (int c = 0; c < 3; ++c) {
            albedo.pixels[3 * i + c] = p.denoising_albedo[c];
            denoising_normal.pixels[3 * i + c] = p.denoising_normal[c];
        }
    }
    image.passes = {std::move(combined), std::move(depth),     std::move(normal),
                    std::move(yarn_id),  std::move(ply_index), std::move(ply_uv),
                    std::move(albedo),   std::move(denoising_normal)};
    return image;
}

}  // namespace purl
