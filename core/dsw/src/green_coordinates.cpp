#include "garmcap/dsw/green_coordinates.h"

#include <cmath>
#include <numbers>

#include "boundary_coordinates.h"

namespace garmcap::dsw {
Expected<GreenCoordinates> greenCoordinates(const Points& polygon, const Points& points) {
  if (auto problem = cageProblem(polygon))
    return Error{"green coordinates: " + *problem};
  if (auto problem = pointsProblem(points))
    return Error{"green coordinates: " + *problem};
  const Eigen::Index n = polygon.rows();
  const Eigen::Index m = points.rows();
  GreenCoordinates gc;
  gc.orientation = twiceSignedArea(polygon) > 0 ? 1.0 : -1.0;
  gc.edgeLengthsCm.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    gc.edgeLengthsCm(j) = (polygon.row((j + 1) % n) - polygon.row(j)).norm();
    if (gc.edgeLengthsCm(j) == 0)
      return Error{"green coordinates: edge from vertex " + std::to_string(j) + " has zero length"};
  }
  gc.vertexWeights.setZero(m, n);
  gc.edgeWeights.setZero(m, n);
  constexpr double kPi = std::numbers::pi;
  for (Eigen::Index k = 0; k < m; ++k) {
    const double x = points(k, 0), y = points(k, 1);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index jn = (j + 1) % n;
      const double ax = polygon(jn, 0) - polygon(j, 0), ay = polygon(jn, 1) - polygon(j, 1);
      const double bx = polygon(j, 0) - x, by = polygon(j, 1) - y;
      const double q = ax * ax + ay * ay;
      const double len = std::sqrt(q);
      const double r = 2 * (ax * bx + ay * by);
      const double tau = -r / (2 * q);  // parameter of the query's projection onto the edge line
      const double cross = ax * by - ay * bx;
      // Distance² to both ends computed directly: S + Q + R = |v_{j+1} - η|² without cancellation.
      const double s0 = bx * bx + by * by;
      const double ex = polygon(jn, 0) - x, ey = polygon(jn, 1) - y;
      const double s1 = ex * ex + ey * ey;
      // Log terms R/(2Q)·(L1 − L0) + L1 = (1 − τ)·L1 + τ·L0, each with its x·log x limit at the
      // ends.
      const double logTerm =
          (s1 == 0 ? 0.0 : (1 - tau) * std::log(s1)) + (s0 == 0 ? 0.0 : tau * std::log(s0));
      double atanTerm = 0;  // (SRT/Q)·(atan1 − atan0), the (4S − R²/Q)·A10 term
      double phiNext = 0, phiThis = 0;
      if (cross != 0) {
        // SRT = sqrt(4SQ − R²) = 2|a × b|, computed without cancellation.
        const double srt = 2 * std::abs(cross);
        const double dAtan = std::atan((2 * q + r) / srt) - std::atan(r / srt);
        atanTerm = srt / q * dAtan;
        // BA = b·(|a| n_out); n_out = orientation·(a_y, −a_x)/|a|.
        const double ba = gc.orientation * (bx * ay - by * ax);
        const double l10 = std::log(s1) - std::log(s0);
        const double a10 = dAtan / srt;
        phiNext = ba / (2 * kPi) * (l10 / (2 * q) - a10 * r / q);
        phiThis = -ba / (2 * kPi) * (l10 / (2 * q) - a10 * (2 + r / q));
      }
      // On the edge's line the double layer of this edge vanishes (principal value).
      gc.vertexWeights(k, jn) += phiNext;
      gc.vertexWeights(k, j) += phiThis;
      gc.edgeWeights(k, j) = -len / (4 * kPi) * (atanTerm + logTerm - 2);
    }
    // On the boundary the double layer jumps: add back the missing part of Σφ = 1 to the
    // vertex or the edge's two vertices, which is the limit from the inside.
    Eigen::Index vertex = -1;
    double t = 0;
    const Eigen::Index edge = exactBoundaryLocation(polygon, x, y, vertex, t);
    if (vertex >= 0 || edge >= 0) {
      const double missing = 1.0 - gc.vertexWeights.row(k).sum();
      if (vertex >= 0) {
        gc.vertexWeights(k, vertex) += missing;
      } else {
        gc.vertexWeights(k, edge) += (1 - t) * missing;
        gc.vertexWeights(k, (edge + 1) % n) += t * missing;
      }
    }
  }
  return gc;
}

Expected<Points> greenDecode(const GreenCoordinates& coordinates, const Points& target) {
  const Eigen::Index n = target.rows();
  if (n != coordinates.vertexWeights.cols())
    return Error{"green decode: target has " + std::to_string(n) + " vertices, source had " +
                 std::to_string(coordinates.vertexWeights.cols())};
  Points scaledNormals(n, 2);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::RowVector2d a = target.row((j + 1) % n) - target.row(j);
    const double len = a.norm();
    if (len == 0)
      return Error{"green decode: target edge from vertex " + std::to_string(j) +
                   " has zero length"};
    // Outward normal of the target, oriented like the source (a cage keeps its orientation).
    const Eigen::RowVector2d normal =
        coordinates.orientation * Eigen::RowVector2d(a.y(), -a.x()) / len;
    scaledNormals.row(j) = normal * (len / coordinates.edgeLengthsCm(j));
  }
  Points out = coordinates.vertexWeights * target + coordinates.edgeWeights * scaledNormals;
  return out;
}

}  // namespace garmcap::dsw
