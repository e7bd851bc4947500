#include "scene/yarn_set_frames.h"

namespace purl {

std::vector<CurveFrames> yarn_set_frames(const YarnCurves& c) {
    std::vector<CurveFrames> frames;
    frames.reserve(c.curve_count());
    for (size_t i = 0; i < c.curve_count(); ++i)
        // Segment indices are global, so the view's base is the set's first point.
        frames.emplace_back(CurveView::separate_segments(c.control_points.data(), static_cast<uint32_t>(c.point_count()),
                                                         c.segment_first.data() + c.segment_offsets[i],
                                                         c.segment_count(i), c.closed[i] != 0));
    return frames;
}

}  // namespace purl
