// Yarn centre-line points by arc length: the inverse of CurveFrames' arc length (v_yarn), so
// explicit plies and fibers can be sampled at even spacing along the yarn and a point on an
// explicit ply can be traced back to the yarn cross-section it came from.
#pragma once
#include <cstdint>
#include <vector>

#include "yarn/curve_frames.h"

namespace purl {

struct CurveParam {
    uint32_t segment = 0;
    float t = 0;
};

class ArcLengthIndex {
public:
    // `frames` must outlive the index.
    explicit ArcLengthIndex(const CurveFrames& frames);

    // The centre-line point whose arc length (CurvePoint::arc_length) is s, m, clamped to
    // [0, length()]; `param` receives its (segment, t). Newton steps on t inside the segment
    // found by binary search; the result's arc length is within 1e-6 of the segment length of s.
    CurvePoint point_at(float s, CurveParam* param = nullptr) const;
    CurveParam locate(float s) const;

    float length() const { return knots_.empty() ? 0.0f : knots_.back(); }  // m
    size_t memory_bytes() const { return sizeof(*this) + knots_.capacity() * sizeof(float); }

private:
    const CurveFrames* frames_;
    std::vector<float> knots_;  // arc length at each segment start, and at the end
};

}  // namespace purl
