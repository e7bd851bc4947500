#include "render/path_regularization.h"

#include <cmath>

namespace purl {

float regularization_alpha(float filter_glossy, float min_bounce_pdf) {
    const float blur_pdf = filter_glossy * min_bounce_pdf;
    return filter_glossy > 0 && blur_pdf < 1.0f ? 0.5f * std::sqrt(1.0f - blur_pdf) : 0.0f;
}

void roughen(ShadingPoint& sp, float min_alpha) {
    if (!(min_alpha > 0)) return;
    if (Bysdf* b = std::get_if<Bysdf>(&sp.bsdf)) {
        b->roughen(min_alpha);
    } else if (PlaceholderYarnBsdf* p = std::get_if<PlaceholderYarnBsdf>(&sp.bsdf)) {
        p->roughness = std::max(p->roughness, std::sqrt(min_alpha));  // its alpha is roughness^2
    }
    // Diffuse meshes have nothing to roughen; the fiber reference stays exact (it is a reference),
    // and the multi-scale and far-field models shade camera hits only.
}

}  // namespace purl
