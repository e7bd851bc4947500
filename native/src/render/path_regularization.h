// Path regularisation (Cycles' "Filter Glossy"): once a path has taken a bounce of low density
// (a diffuse-like bounce spreads its rays over the hemisphere), the glossy lobes it meets later
// are made rougher. A narrow highlight seen through a diffuse bounce is a caustic the path tracer
// finds only by chance, and the white fireflies of knits at low spp come from exactly such paths:
// a camera ray scatters off a yarn's body lobe, meets another yarn at a grazing angle and there
// catches a small light in the specular reflection, with f = 2-9 /sr (docs/denoising.md).
//
// The rule is Cycles': with p the smallest solid-angle pdf of the bounces so far and s the
// setting, a glossy lobe's GGX alpha becomes at least 0.5 sqrt(1 - s p) while s p < 1. It changes
// only the lobes' shapes, not their energies, and never touches camera hits, so the image stays
// sharp where it is seen directly; it biases glossy reflections of glossy light seen indirectly.
#pragma once
#include "render/shading.h"

namespace purl {

// The smallest GGX alpha the path's next glossy lobes may have (0: leave them).
float regularization_alpha(float filter_glossy, float min_bounce_pdf);

// Raises the glossy lobes of the shading point's model to at least `min_alpha`.
void roughen(ShadingPoint& sp, float min_alpha);

}  // namespace purl
