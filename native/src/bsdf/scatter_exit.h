// The small context every scattering model's eval, eval_pdf and sample take: what the ray
// toward wi meets on its way out of the yarn. The BYSDF attenuates its transmission along it;
// surfaces, the fiber BCSDF and the models that attenuate on their own (multi-scale, far field)
// ignore it. The interface itself is render/scattering.h.
#pragma once
#include "math/vec.h"
#include "yarn/ply_crossings.h"

namespace purl {

struct ScatterExit {
    float chord = 0;                      // path inside the yarn, yarn radii; 0: none or unknown
    const PlyCrossings* plies = nullptr;  // traced ply crossing: what the ray crosses; null: not traced
};

// For `sample`: the exit of the sampled direction (local frame, pointing away), asked once the
// direction is chosen and before the model evaluates it, so the sample's f is final in one pass.
// What it points to stays valid until the next call.
class ExitQuery {
public:
    virtual ScatterExit toward(Vec3 wi_local) = 0;

protected:
    ~ExitQuery() = default;
};

}  // namespace purl
