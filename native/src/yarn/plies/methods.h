// The three ply search methods behind trace_plies (implicit_plies.h), one file each
// (the circular one, small, in circular.h).
#pragma once
#include "yarn/implicit_plies.h"
#include "yarn/plies/circular.h"

namespace purl::plies {

// elliptical (exact.cpp): `frames` caches the few segments the ray's stretch spans; `at` is the
// projection of the tube entry, without its frame.
PlyHit trace_exact(const CachedCurve& frames, const PlyQuery& q, const CentrelineProjection& at,
                   const PlyTraceOptions& options, PlySearchStats& stats);
// local (local.cpp): the yarn modelled around `at`; at_entry: `at` is the projection of the
// tube entry itself (else of a point near it).
PlyHit trace_local(const PlyQuery& q, const CentrelineProjection& at, const PlyTraceOptions& options, bool at_entry);
}  // namespace purl::plies
