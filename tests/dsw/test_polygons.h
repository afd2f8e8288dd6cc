#pragma once
// Polygons and query points shared by the dsw tests and benchmarks: random simple polygons
// (convex and concave, star-shaped around the origin) at centimetre scale, and the concave
// bodice-like draft polygon of research/anchors_algorithms.md.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw::testing {

/// Concave bodice-like polygon (cm): a reflex vertex at (12, 22).
inline Points bodicePolygon() {
  Points p(7, 2);
  p << 0, 0, 24, 0, 24, 30, 14, 30, 12, 22, 10, 30, 0, 30;
  return p;
}

/// Strictly convex polygon with n vertices on an ellipse (semi-axes in cm), random angles.
inline Points randomConvex(int n, std::mt19937& rng, double ax = 30, double ay = 20) {
  std::uniform_real_distribution<double> u(0, 2 * std::numbers::pi);
  std::vector<double> angles(static_cast<std::size_t>(n));
  for (auto& a : angles)
    a = u(rng);
  std::sort(angles.begin(), angles.end());
  Points p(n, 2);
  for (int i = 0; i < n; ++i)
    p.row(i) << ax * std::cos(angles[static_cast<std::size_t>(i)]) + 5,
        ay * std::sin(angles[static_cast<std::size_t>(i)]) - 3;
  return p;
}

/// Star-shaped (so simple) polygon, usually concave: sorted angles with jitter and random radii.
inline Points randomStar(int n, std::mt19937& rng, double radius = 30) {
  std::uniform_real_distribution<double> jitter(0.1, 0.9), r(0.35, 1.0);
  Points p(n, 2);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * (i + jitter(rng)) / n;
    const double rr = radius * r(rng);
    p.row(i) << rr * std::cos(a) + 7, rr * std::sin(a) + 11;
  }
  return p;
}

/// Uniform random points in the polygon's bounding box grown by `grow` (fraction of its size).
inline Points randomPointsAround(const Points& polygon, int m, std::mt19937& rng,
                                 double grow = 0.5) {
  const Eigen::RowVector2d lo = polygon.colwise().minCoeff(), hi = polygon.colwise().maxCoeff();
  const Eigen::RowVector2d size = hi - lo;
  std::uniform_real_distribution<double> ux(lo.x() - grow * size.x(), hi.x() + grow * size.x());
  std::uniform_real_distribution<double> uy(lo.y() - grow * size.y(), hi.y() + grow * size.y());
  Points q(m, 2);
  for (int k = 0; k < m; ++k)
    q.row(k) << ux(rng), uy(rng);
  return q;
}

/// Points at distance d from edges (both sides), at random positions along random edges.
inline Points pointsNearEdges(const Points& polygon, int m, double d, std::mt19937& rng) {
  std::uniform_int_distribution<Eigen::Index> edge(0, polygon.rows() - 1);
  std::uniform_real_distribution<double> t(0.05, 0.95);
  std::bernoulli_distribution side;
  Points q(m, 2);
  for (int k = 0; k < m; ++k) {
    const Eigen::Index i = edge(rng), j = (i + 1) % polygon.rows();
    const Eigen::RowVector2d a = polygon.row(i), b = polygon.row(j);
    const Eigen::RowVector2d dir = (b - a).normalized();
    const Eigen::RowVector2d normal(-dir.y(), dir.x());
    q.row(k) = a + t(rng) * (b - a) + (side(rng) ? d : -d) * normal;
  }
  return q;
}

}  // namespace garmcap::dsw::testing
