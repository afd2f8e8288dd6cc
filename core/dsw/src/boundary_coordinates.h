#pragma once
// Coordinates of a point on the cage boundary, shared by the coordinate kernels: on a vertex
// the unit row, on an edge the two segment coordinates. Every coordinate with linear precision
// that is continuous up to the boundary has these values there.

#include <Eigen/Core>

#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

/// If (x, y) lies on the boundary of `polygon` — exactly when tolCm == 0 (same vertex, or
/// zero cross product with the point strictly between the edge's ends), else within tolCm —
/// writes its boundary coordinates into `out` (length N) and returns true; otherwise leaves
/// `out` alone and returns false.
template <typename Row>
bool boundaryCoordinates(const Points& polygon, double x, double y, double tolCm, Row&& out);

/// Index of the edge (i -> i+1) the point lies on exactly, with its parameter t in (0, 1),
/// or -1 when it lies on no edge or exactly on a vertex; `vertex` receives the vertex index
/// or -1.
Eigen::Index exactBoundaryLocation(const Points& polygon, double x, double y, Eigen::Index& vertex,
                                   double& t);

template <typename Row>
bool boundaryCoordinates(const Points& polygon, double x, double y, double tolCm, Row&& out) {
  const Eigen::Index n = polygon.rows();
  if (tolCm == 0) {
    Eigen::Index vertex = -1;
    double t = 0;
    const Eigen::Index edge = exactBoundaryLocation(polygon, x, y, vertex, t);
    if (vertex >= 0) {
      out.setZero();
      out(vertex) = 1.0;
      return true;
    }
    if (edge >= 0) {
      out.setZero();
      out(edge) = 1.0 - t;
      out((edge + 1) % n) = t;
      return true;
    }
    return false;
  }
  // Nearest boundary feature within the tolerance.
  double best = tolCm;
  Eigen::Index bestEdge = -1;
  double bestT = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    const double ax = polygon(i, 0), ay = polygon(i, 1);
    const double ex = polygon(j, 0) - ax, ey = polygon(j, 1) - ay;
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0 ? ((x - ax) * ex + (y - ay) * ey) / len2 : 0.0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    const double d = std::hypot(ax + t * ex - x, ay + t * ey - y);
    if (d <= best) {
      best = d;
      bestEdge = i;
      bestT = t;
    }
  }
  if (bestEdge < 0)
    return false;
  out.setZero();
  out(bestEdge) = 1.0 - bestT;
  out((bestEdge + 1) % n) += bestT;
  return true;
}

}  // namespace garmcap::dsw
