#include "garmcap/dsw/polygon.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace garmcap::dsw {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Exact-sign orientation of (a, b, c) as far as double allows; used only for the simplicity
// check, where a wrong sign on a near-touching pair merely reports "not simple" slightly early.
double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return cross(b - a, c - a);
}

bool onSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

bool segmentsIntersect(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                       const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  const double d1 = orient(q1, q2, p1);
  const double d2 = orient(q1, q2, p2);
  const double d3 = orient(p1, p2, q1);
  const double d4 = orient(p1, p2, q2);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  if (d1 == 0 && onSegment(q1, q2, p1))
    return true;
  if (d2 == 0 && onSegment(q1, q2, p2))
    return true;
  if (d3 == 0 && onSegment(p1, p2, q1))
    return true;
  if (d4 == 0 && onSegment(p1, p2, q2))
    return true;
  return false;
}

}  // namespace

Points toPoints(const drafts::Polyline& polyline) {
  Points p(static_cast<Eigen::Index>(polyline.size()), 2);
  for (std::size_t i = 0; i < polyline.size(); ++i)
    p.row(static_cast<Eigen::Index>(i)) = polyline[i].transpose();
  return p;
}

drafts::Polyline toPolyline(const Points& points) {
  drafts::Polyline out;
  out.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    out.emplace_back(points(i, 0), points(i, 1));
  return out;
}

double twiceSignedArea(const Points& polygon) {
  const Eigen::Index n = polygon.rows();
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    sum += polygon(i, 0) * polygon(j, 1) - polygon(j, 0) * polygon(i, 1);
  }
  return sum;
}

double boundingDiagonal(const Points& polygon) {
  if (polygon.rows() == 0)
    return 0;
  return (polygon.colwise().maxCoeff() - polygon.colwise().minCoeff()).norm();
}

std::optional<std::string> cageProblem(const Points& polygon) {
  const Eigen::Index n = polygon.rows();
  if (n < 3)
    return "polygon has " + std::to_string(n) + " vertices; at least 3 are needed";
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(polygon(i, 0)) || !std::isfinite(polygon(i, 1)))
      return "polygon vertex " + std::to_string(i) + " is not finite";
  }
  // Distinct vertices after dropping consecutive repeats.
  std::vector<Eigen::Index> distinct;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (polygon.row(i) != polygon.row((i + 1) % n))
      distinct.push_back(i);
  }
  if (distinct.size() < 3)
    return "polygon has only " + std::to_string(distinct.size()) +
           " distinct vertices (repeated vertices)";
  const double diag = boundingDiagonal(polygon);
  const double area2 = twiceSignedArea(polygon);
  // Zero area up to rounding of the shoelace sum: collinear vertices.
  if (!(std::abs(area2) > 1e-12 * diag * diag))
    return "polygon has zero area (collinear vertices)";
  // Simplicity: no two non-adjacent edges (between distinct vertices) touch.
  const std::size_t m = distinct.size();
  // Edge bounding boxes: segments that touch have overlapping boxes, and most pairs of a draft
  // region's edges are far apart, so the box test skips the orientation tests for them.
  std::vector<Eigen::Vector2d> lo(m), hi(m);
  for (std::size_t a = 0; a < m; ++a) {
    const Eigen::Vector2d p1 = polygon.row(distinct[a]).transpose();
    const Eigen::Vector2d p2 = polygon.row(distinct[(a + 1) % m]).transpose();
    lo[a] = p1.cwiseMin(p2);
    hi[a] = p1.cwiseMax(p2);
  }
  for (std::size_t a = 0; a < m; ++a) {
    const Eigen::Vector2d p1 = polygon.row(distinct[a]).transpose();
    const Eigen::Vector2d p2 = polygon.row(distinct[(a + 1) % m]).transpose();
    for (std::size_t b = a + 2; b < m; ++b) {
      if (a == 0 && b == m - 1)
        continue;  // adjacent through the wrap-around
      if ((lo[b].array() > hi[a].array()).any() || (hi[b].array() < lo[a].array()).any())
        continue;
      const Eigen::Vector2d q1 = polygon.row(distinct[b]).transpose();
      const Eigen::Vector2d q2 = polygon.row(distinct[(b + 1) % m]).transpose();
      if (segmentsIntersect(p1, p2, q1, q2))
        return "polygon is not simple: edge from vertex " + std::to_string(distinct[a]) +
               " crosses edge from vertex " + std::to_string(distinct[b]);
    }
  }
  return std::nullopt;
}

bool isConvex(const Points& polygon) {
  const Eigen::Index n = polygon.rows();
  const double sign = twiceSignedArea(polygon) > 0 ? 1.0 : -1.0;
  const double diag = boundingDiagonal(polygon);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d a = polygon.row((i + n - 1) % n).transpose();
    const Eigen::Vector2d b = polygon.row(i).transpose();
    const Eigen::Vector2d c = polygon.row((i + 1) % n).transpose();
    // A reflex turn larger than rounding noise makes the polygon non-convex.
    if (sign * cross(b - a, c - b) < -1e-12 * diag * diag)
      return false;
  }
  return true;
}

std::optional<std::string> pointsProblem(const Points& points) {
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (!std::isfinite(points(i, 0)) || !std::isfinite(points(i, 1)))
      return "point " + std::to_string(i) + " is not finite";
  }
  return std::nullopt;
}

}  // namespace garmcap::dsw
