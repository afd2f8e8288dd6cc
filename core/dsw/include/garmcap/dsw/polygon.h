#pragma once
// Point sets and polygons as Eigen matrices, and the checks every coordinate function runs on
// its cage polygon before computing weights.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "garmcap/drafts/pattern.h"

namespace garmcap::dsw {

/// N×2, one point per row (x, y) in cm. Column-major, so all x then all y: the batched
/// coordinate kernels run down the columns.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// Converts a draft polyline to an N×2 matrix and back.
Points toPoints(const drafts::Polyline& polyline);
drafts::Polyline toPolyline(const Points& points);

/// Twice the signed area (shoelace); positive for counter-clockwise in y-up axes, which is
/// clockwise as seen on paper in the project's y-down coordinates.
double twiceSignedArea(const Points& polygon);

/// Length of the bounding-box diagonal, the scale used for relative tolerances.
double boundingDiagonal(const Points& polygon);

/// Why `polygon` cannot be a cage for generalized barycentric coordinates, or nullopt when it
/// can: fewer than 3 vertices, a non-finite coordinate, fewer than 3 distinct vertices, zero
/// area (all vertices collinear), or two non-adjacent edges that cross (not simple).
/// Repeated consecutive vertices alone are accepted: the coordinates split the vertex weight
/// between the copies, which decodes correctly. The message names the vertex or edges.
std::optional<std::string> cageProblem(const Points& polygon);

/// Whether every vertex turns the same way (collinear vertices allowed: weakly convex).
/// Assumes cageProblem(polygon) is nullopt.
bool isConvex(const Points& polygon);

/// Why `points` cannot be encoded (a non-finite coordinate, naming the row), or nullopt.
std::optional<std::string> pointsProblem(const Points& points);

}  // namespace garmcap::dsw
