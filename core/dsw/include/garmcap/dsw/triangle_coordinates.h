#pragma once
// Triangular barycentric coordinates through a triangulation of the cage (the seed's §4.3.1):
// each point is encoded by the three vertices of one triangle.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

using Triangle = std::array<Eigen::Index, 3>;  // vertex indices into the cage

/// Ear-clipping triangulation of a simple polygon (N×2, any orientation; repeated
/// consecutive vertices are skipped). N−2 triangles for N distinct vertices, each listed in
/// the polygon's orientation. Errors: the cage fails cageProblem(), or no ear is found
/// (only for polygons that are simple up to rounding).
Expected<std::vector<Triangle>> triangulatePolygon(const Points& polygon);

/// M×N weights, three non-zeros per row: the barycentric coordinates of each point in the
/// triangle that contains it, or, for a point outside every triangle (outside the cage), the
/// triangle whose smallest barycentric coordinate is largest (the nearest in that sense),
/// extrapolated linearly. Rows sum to 1 and reproduce the point everywhere. Continuous inside
/// (shared edges get the same segment coordinates), not smooth across triangle edges.
Expected<Eigen::MatrixXd> triangleCoordinates(const Points& polygon, const Points& points);

/// The same with a given triangulation (e.g. reused for many point sets).
Eigen::MatrixXd triangleCoordinates(const Points& polygon, const std::vector<Triangle>& triangles,
                                    const Points& points);

}  // namespace garmcap::dsw
