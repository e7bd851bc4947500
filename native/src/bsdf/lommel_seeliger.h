// Lommel-Seeliger single-scattering term of a half-space of isotropic scatterers
// (unit single-scattering albedo), and its directional albedo in closed form.
#pragma once
#include "math/vec.h"

namespace purl {

// LS(wo, wi) = 1 / (4 pi (cos_o + cos_i)), cosines on the reflecting side (> 0), 1/sr.
inline float lommel_seeliger(float cos_o, float cos_i) { return kInv4Pi / (cos_o + cos_i); }

// Integral of LS * cos_i over the hemisphere: (1 - mu ln(1 + 1/mu)) / 2, from 0.153 at
// normal incidence up to 1/2 at grazing.
inline float lommel_seeliger_albedo(float mu) {
    if (!(mu > 1e-12f)) return 0.5f;
    return 0.5f * (1.0f - mu * std::log1p(1.0f / mu));
}

}  // namespace purl
