#pragma once
// Horizontal cross-sections of a closed triangle mesh and their tape-measure circumference.

#include <Eigen/Core>
#include <vector>

#include "garmcap/calib/mesh.h"

namespace garmcap::calib {

/// One closed loop of a horizontal slice, points (x, z) in mesh units, in order, not repeated.
using SliceLoop = std::vector<Eigen::Vector2d>;

/// Cuts `mesh` with the plane y = `height`. Returns the closed loops (one per connected
/// component of the cross-section). Vertices lying exactly on the plane count as above it, so a
/// ring of vertices at `height` is returned exactly. Open chains (from an open mesh) are dropped.
std::vector<SliceLoop> sliceMesh(const TriMesh& mesh, double height);

/// Convex hull (counter-clockwise) of all points of `loops`.
std::vector<Eigen::Vector2d> convexHull(const std::vector<SliceLoop>& loops);

/// Perimeter of a closed polygon.
double polygonPerimeter(const std::vector<Eigen::Vector2d>& polygon);

/// Signed area (positive for counter-clockwise in the x-z plane).
double polygonArea(const std::vector<Eigen::Vector2d>& polygon);

/// Even-odd point-in-polygon test.
bool pointInPolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

}  // namespace garmcap::calib
