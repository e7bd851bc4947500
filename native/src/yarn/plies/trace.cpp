// trace_plies: the method the options choose, for one query.
#include "yarn/plies/methods.h"

namespace purl {

PlyHit trace_plies(const PlyQuery& q, const PlyTraceOptions& options, PlySearchStats* stats) {
    if (stats) *stats = {};
    const YarnTubeHit& hit = q.ray;
    switch (options.cross_section) {
        case PlyCrossSection::circular:
            return plies::trace_circular(q, project_to_centreline(q.frames, hit.point, hit.segment, hit.t));
        case PlyCrossSection::local:
            if (q.around) return plies::trace_local(q, *q.around, options, false);
            return plies::trace_local(q, project_to_centreline(q.frames, hit.point, hit.segment, hit.t), options, true);
        case PlyCrossSection::elliptical: break;
    }
    // One cache of segment expansions for the whole query, starting with the projection's.
    const CachedCurve cache(q.frames);
    PlySearchStats ignored;
    return plies::trace_exact(cache, q, project_to_centreline_unframed(cache, hit.point, hit.segment, hit.t), options,
                              stats ? *stats : ignored);
}

}  // namespace purl
