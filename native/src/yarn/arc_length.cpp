#include "yarn/arc_length.h"

#include <algorithm>
#include <cmath>

namespace purl {

ArcLengthIndex::ArcLengthIndex(const CurveFrames& frames) : frames_(&frames) {
    const uint32_t n = frames.segment_count();
    if (n == 0) return;
    knots_.resize(n + 1);
    for (uint32_t k = 0; k < n; ++k) knots_[k] = frames.evaluate(k, 0.0f).arc_length;
    knots_[n] = frames.evaluate(n - 1, 1.0f).arc_length;
}

CurvePoint ArcLengthIndex::point_at(float s, CurveParam* param) const {
    const uint32_t n = static_cast<uint32_t>(knots_.size()) - 1;
    s = clamp(s, 0.0f, length());
    // Last segment starting at or before s.
    uint32_t k = static_cast<uint32_t>(std::upper_bound(knots_.begin(), knots_.end(), s) - knots_.begin());
    k = std::min(std::max(k, 1u) - 1, n - 1);
    const float a = knots_[k], b = knots_[k + 1], span = b - a;
    float lo = 0, hi = 1;
    float t = span > 0 ? clamp((s - a) / span, 0.0f, 1.0f) : 0.0f;
    CurvePoint c = frames_->evaluate(k, t);
    // Newton on arc_length(t) = s with speed as the slope, kept inside a shrinking bracket.
    for (int step = 0; step < 8; ++step) {
        const float error = c.arc_length - s;
        if (std::fabs(error) <= 1e-6f * span) break;
        if (error > 0) hi = t; else lo = t;
        float next = c.speed > 0 ? t - error / c.speed : 0.5f * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
        t = next;
        c = frames_->evaluate(k, t);
    }
    if (param) *param = {k, t};
    return c;
}

CurveParam ArcLengthIndex::locate(float s) const {
    CurveParam p;
    point_at(s, &p);
    return p;
}

}  // namespace purl
