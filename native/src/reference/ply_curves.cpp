#include "reference/ply_curves.h"

#include "yarn/arc_length.h"
#include "reference/spline_fit.h"
#include "yarn/ply_helix.h"

namespace purl {

void append_ply_curves(const CurveFrames& frames, const YarnDescription& d, const CurveSampling& plan,
                       uint32_t yarn_curve, int32_t id, YarnCurves& out, std::vector<PlyCurveOrigin>& origins) {
    const int plies = d.plies();
    const ArcLengthIndex index(frames);
    const YarnTwist twist = yarn_twist(frames, d);
    const std::vector<float> arcs = sample_arc_lengths(plan, index.length());
    std::vector<std::vector<Point4d>> samples(plies, std::vector<Point4d>(arcs.size()));
    for (size_t j = 0; j < arcs.size(); ++j) {
        const CurvePoint yarn = index.point_at(arcs[j]);
        for (int i = 0; i < plies; ++i) {
            const PlyCentre c = ply_centre(yarn, d, twist, i);
            samples[i][j] = {{c.position.x, c.position.y, c.position.z, c.radius}};
        }
    }
    for (int i = 0; i < plies; ++i) {
        const std::vector<Vec4> points = fit_samples(plan, samples[i]);
        out.add_curve(points.data(), points.size(), plan.closed, id);
        origins.push_back({yarn_curve, i, 0.0f, plan.step});
    }
}

}  // namespace purl
