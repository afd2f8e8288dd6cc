#include "garmcap/dsw/triangle_coordinates.h"

#include <cmath>
#include <limits>
#include <list>

namespace garmcap::dsw {
namespace {

double cross3(const Points& p, Eigen::Index a, Eigen::Index b, Eigen::Index c) {
  return (p(b, 0) - p(a, 0)) * (p(c, 1) - p(a, 1)) - (p(b, 1) - p(a, 1)) * (p(c, 0) - p(a, 0));
}

// Whether vertex p lies inside or on triangle (a, b, c) of orientation `sign`.
bool inTriangle(const Points& pts, Eigen::Index a, Eigen::Index b, Eigen::Index c, Eigen::Index p,
                double sign) {
  return sign * cross3(pts, a, b, p) >= 0 && sign * cross3(pts, b, c, p) >= 0 &&
         sign * cross3(pts, c, a, p) >= 0;
}

}  // namespace

Expected<std::vector<Triangle>> triangulatePolygon(const Points& polygon) {
  if (auto problem = cageProblem(polygon))
    return Error{"triangulation: " + *problem};
  const Eigen::Index n = polygon.rows();
  std::vector<Eigen::Index> ring;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (polygon.row(i) != polygon.row((i + 1) % n))
      ring.push_back(i);
  }
  const double sign = twiceSignedArea(polygon) > 0 ? 1.0 : -1.0;
  std::vector<Triangle> triangles;
  // Clip the ear with the best (largest) minimum angle proxy first would be nicer; the first
  // valid ear keeps the triangulation deterministic and depends only on vertex order, which
  // is what grading needs (same triangles for source and target drafts).
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    // Prefer strictly convex ears; fall back to degenerate (collinear) ones.
    for (int pass = 0; pass < 2 && !clipped; ++pass) {
      for (std::size_t i = 0; i < m; ++i) {
        const Eigen::Index a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
        const double turn = sign * cross3(polygon, a, b, c);
        if (pass == 0 ? !(turn > 0) : turn < 0)
          continue;
        bool blocked = false;
        for (std::size_t j = 0; j < m && !blocked; ++j) {
          const Eigen::Index p = ring[j];
          if (p == a || p == b || p == c)
            continue;
          if (polygon.row(p) == polygon.row(a) || polygon.row(p) == polygon.row(b) ||
              polygon.row(p) == polygon.row(c))
            continue;
          blocked = turn > 0 && inTriangle(polygon, a, b, c, p, sign);
        }
        if (blocked)
          continue;
        triangles.push_back({a, b, c});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
        break;
      }
    }
    if (!clipped)
      return Error{"triangulation: no ear found (polygon nearly self-intersecting)"};
  }
  triangles.push_back({ring[0], ring[1], ring[2]});
  return triangles;
}

Eigen::MatrixXd triangleCoordinates(const Points& polygon, const std::vector<Triangle>& triangles,
                                    const Points& points) {
  const Eigen::Index m = points.rows();
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(m, polygon.rows());
  for (Eigen::Index k = 0; k < m; ++k) {
    const double x = points(k, 0), y = points(k, 1);
    double bestMin = -std::numeric_limits<double>::infinity();
    std::array<double, 3> best{1, 0, 0};
    const Triangle* bestTri = nullptr;
    for (const Triangle& t : triangles) {
      const double ax = polygon(t[0], 0), ay = polygon(t[0], 1);
      const double bx = polygon(t[1], 0), by = polygon(t[1], 1);
      const double cx = polygon(t[2], 0), cy = polygon(t[2], 1);
      const double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      if (area == 0)
        continue;  // a degenerate ear of collinear vertices encodes nothing
      const double l0 = ((bx - x) * (cy - y) - (by - y) * (cx - x)) / area;
      const double l1 = ((cx - x) * (ay - y) - (cy - y) * (ax - x)) / area;
      const double l2 = 1.0 - l0 - l1;
      const double lo = std::min({l0, l1, l2});
      if (lo > bestMin) {
        bestMin = lo;
        best = {l0, l1, l2};
        bestTri = &t;
      }
    }
    if (bestTri == nullptr)
      continue;  // unreachable for a cage with non-zero area
    for (int i = 0; i < 3; ++i)
      weights(k, (*bestTri)[static_cast<std::size_t>(i)]) += best[static_cast<std::size_t>(i)];
  }
  return weights;
}

Expected<Eigen::MatrixXd> triangleCoordinates(const Points& polygon, const Points& points) {
  if (auto problem = pointsProblem(points))
    return Error{"triangle coordinates: " + *problem};
  auto triangles = triangulatePolygon(polygon);
  if (!triangles)
    return Error{"triangle coordinates: " + triangles.error().message};
  return triangleCoordinates(polygon, *triangles, points);
}

}  // namespace garmcap::dsw
