#pragma once
// Wachspress coordinates (Wachspress 1975; the seed's eq. 4.7-4.8) for convex polygons.

#include <Eigen/Core>

#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

/// Weights of `points` (M×2) with respect to the convex cage `polygon` (N×2, any orientation,
/// collinear vertices allowed: they get weight 0 away from their edges). Returns M×N rows
/// that sum to 1 and reproduce the point inside and on the boundary (segment coordinates on
/// an edge, the unit row on a vertex). Outside the polygon the rational extension is
/// returned; it has poles there, so exterior rows can be large (see docs/dsw.md).
/// Errors: the cage fails cageProblem() or is not convex (Wachspress coordinates are not
/// defined inside a concave polygon: the seed's figure 4.8), a point is not finite, or a point
/// lies on a pole of the exterior extension.
Expected<Eigen::MatrixXd> wachspressCoordinates(const Points& polygon, const Points& points);

}  // namespace garmcap::dsw
