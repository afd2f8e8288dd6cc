#pragma once
// Private to the drafts library: polyline cuts that take the cumulative arc lengths
// (cumulativeLengths) from the caller, for a long polyline cut at several places (openDarts on
// the finely sampled waist curves). Same results as the public functions of the same names.

#include <vector>

#include "garmcap/drafts/geometry_polyline.h"

namespace garmcap::drafts::detail {

/// pointAtLength(pl, s) with cum = cumulativeLengths(pl).
Point2 pointAtLength(const Polyline& pl, const std::vector<double>& cum, double s);
/// subPolyline(pl, s0, s1) with cum = cumulativeLengths(pl).
Polyline subPolyline(const Polyline& pl, const std::vector<double>& cum, double s0, double s1);

}  // namespace garmcap::drafts::detail
