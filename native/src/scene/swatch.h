// Procedural cloth swatches: yarn centre-lines for a stockinette knit and for plain,
// twill and satin weaves, in metres, Z-up, lying in the XY plane around the origin.
//
// Knit: each course (row of loops) is one open curve along +X; courses are stacked along +Y
// and each loop is pulled through the loop below it (the technical face looks toward +Z).
// Weaves: warp yarns run along Y, weft yarns along X; at every crossing one yarn sits
// `crimp` above the mid-plane and the other the same distance below, per the weave pattern.
// Shapes are sized in units of the yarn radius R so the yarns never intersect: measured
// clearance between distinct yarns >= 2.2 R (knit) and >= 2.1 R (weaves), against 2 R for
// touching tubes. All curves are B-spline chains interpolating their shape.
#pragma once
#include <string>

#include "scene/curves.h"

namespace purl {

enum class SwatchKind { Knit, Plain, Twill, Satin };

struct SwatchOptions {
    float yarn_radius = 0.5e-3f;  // m, R; every size below defaults to a multiple of R
    int courses = 10;             // knit: rows of loops (one curve each)
    int wales = 5;                // knit: loops per course
    int warps = 10;               // weaves: yarns along Y
    int wefts = 10;               // weaves: yarns along X
    // m, centre-line spacing: between wales for a knit (courses follow in proportion),
    // between neighbouring yarns for a weave. 0 picks the tightest non-intersecting
    // spacing (9.5 R knit, 5 R weave); anything tighter is rejected.
    float spacing = 0.0f;
    int twill_over = 2;   // twill: a warp floats over this many wefts ...
    int twill_under = 1;  // ... then under this many (2/1 or 2/2 twill)
};

// Throws InputError (file "swatch") for counts or sizes out of range.
YarnCurves generate_swatch(SwatchKind kind, const SwatchOptions& options);

// "knit", "plain", "twill" or "satin"; anything else throws InputError listing them.
SwatchKind parse_swatch_kind(const std::string& name);

// Default wale (knit) or yarn (weave) spacing for a yarn radius, m.
float default_swatch_spacing(SwatchKind kind, float yarn_radius);

}  // namespace purl
