// Shared by the image tests that compare renders with stored reference EXRs
// (ExplicitImages, Fig7Images, MultiscaleImages): the Combined pass as RGB, writing a
// reference, and relative RMSE of block means (block means average the Monte Carlo noise
// down, so the metric sees changes of look, not single noisy pixels).
#pragma once
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "io/image_io.h"
#include "render/renderer.h"

namespace purl {

inline ImageRGB combined_rgb(const RenderResult& r) {
    const ImagePass* combined = r.image.find("Combined");
    ImageRGB out;
    out.width = r.image.width;
    out.height = r.image.height;
    out.rgb.resize(size_t(out.width) * out.height * 3);
    for (size_t i = 0; i < size_t(out.width) * out.height; ++i)
        for (int c = 0; c < 3; ++c) out.rgb[i * 3 + c] = combined->pixels[i * combined->channels() + c];
    return out;
}


// sqrt(mean((a - b)^2)) / mean(b) over the RGB of block x block block means.
inline double block_relative_rmse(const ImageRGB& a, const ImageRGB& b, int block) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    const int w = a.width / block, h = a.height / block;
    const double area = double(block) * block;
    double se = 0, sum = 0;
    for (int by = 0; by < h; ++by)
        for (int bx = 0; bx < w; ++bx)
            for (int c = 0; c < 3; ++c) {
                double ma = 0, mb = 0;
                for (int y = by * block; y < (by + 1) * block; ++y)
                    for (int x = bx * block; x < (bx + 1) * block; ++x) {
                        const size_t i = (size_t(y) * a.width + x) * 3 + c;
                        ma += a.rgb[i];
                        mb += b.rgb[i];
                    }
                se += (ma - mb) * (ma - mb) / (area * area);
                sum += mb / area;
            }
    const double n = double(w) * h * 3;
    return std::sqrt(se / n) / std::max(sum / n, 1e-12);
}

}  // namespace purl
