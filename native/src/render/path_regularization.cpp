#include "render/path_regularization.h"

#include <cmath>

namespace purl {

float regularization_alpha(float filter_glossy, float min_bounce_pdf) {
    const float blur_pdf = filter_glossy * min_bounce_pdf;
    return filter_glossy > 0 && blur_pdf < 1.0f ? 0.5f * std::sqrt(1.0f - blur_pdf) : 0.0f;
}

void roughen(ShadingPoint& sp, float min_alpha) {
    if (min_alpha > 0) sp.bsdf.roughen(min_alpha);
}

}  // namespace purl
