// Pixel footprint on a yarn, in the yarn's azimuthal offset h (Khattar et al. 2024, sections
// 4.2 and 5.2). h is the signed distance of a ray from the yarn's centre-line, measured in
// the azimuthal plane (perpendicular to the yarn tangent) and divided by the yarn radius, as
// in hair models: h = +-1 grazes the silhouettes, equal steps of h are equal projected widths.
//
// The camera ray's one-pixel differentials are intersected with the yarn's silhouette plane
// (through the centre-line, perpendicular to the ray's projection onto the azimuthal plane) and
// measured along the "across" direction; the footprint of a box pixel is then
// h0 +- scale (|dh/dx| + |dh/dy|) / 2, clamped to the yarn, [-1, 1]. Measuring in this plane,
// not on the tube surface, keeps a pixel's coverage the same near the silhouettes as in the
// middle, which is what an integral over h needs.
//
// The yarn is taken as the straight cylinder of the centre-line point closest to the hit.
#pragma once
#include "math/ray.h"
#include "yarn/curve_frames.h"

namespace purl {

struct AzimuthalFootprint {
    float h0 = 0;          // the ray's own offset, in [-1, 1]
    float h1 = 0, h2 = 0;  // covered range, -1 <= h1 <= h0 <= h2 <= 1
    float raw_width = 0;   // unclamped h extent of the footprint (2: one pixel spans the yarn's diameter)
    Vec3 across;           // unit, perpendicular to the yarn tangent and to the ray: direction of +h
    bool valid = false;    // false: no differentials, or the ray runs along the yarn; then h1 = h2 = h0
    bool along_yarn = false;  // the ray is within ~0.06 deg of the yarn tangent: h is undefined (h0 = 0)

    float width() const { return h2 - h1; }
    // The footprint reaches both silhouettes.
    bool covers_yarn() const { return valid && h1 <= -1.0f && h2 >= 1.0f; }
};

// Footprint of `ray` at its hit on the yarn of centre-line point `axis` (position, tangent and
// radius; its frame fields are not used). `hit_point` (m) is where the ray met the tube; it only
// orients `across` when the ray runs along the yarn. `scale` (pixels) multiplies the
// one-pixel differentials (e.g. 1/sqrt(spp) to follow the sample density; 1 = one pixel).
// Differential origins may lag behind ray.origin: each differential is used as a line.
AzimuthalFootprint yarn_footprint(const Ray& ray, Vec3 hit_point, const CurvePoint& axis, float scale = 1.0f);

// h of the straight line through `origin` along `direction` (any length) around `axis`, for
// the orientation `across` of a footprint. Parallel lines: exact; others: where they cross the
// silhouette plane. Returns NaN when the line is parallel to that plane.
float line_offset(Vec3 origin, Vec3 direction, const CurvePoint& axis, Vec3 across);

}  // namespace purl
