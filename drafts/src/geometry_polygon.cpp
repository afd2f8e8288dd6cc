#include "garmcap/drafts/geometry_polygon.h"

#include <cmath>

namespace garmcap::drafts {

namespace {

double cross(const Point2& a, const Point2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Do segments [a0, a1] and [b0, b1] share at least one point (touching counts)?
bool segmentsTouch(const Point2& a0, const Point2& a1, const Point2& b0, const Point2& b1) {
  if (intersectSegments(a0, a1, b0, b1))
    return true;
  // intersectSegments leaves out collinear overlaps: check them here (an edge running back
  // along another is a self-intersection of the outline).
  const Point2 r = a1 - a0;
  const double rn = r.norm();
  if (rn < kGeometryEpsCm)
    return false;
  if (std::abs(cross(r, b0 - a0)) / rn > kGeometryEpsCm ||
      std::abs(cross(r, b1 - a0)) / rn > kGeometryEpsCm) {
    return false;
  }
  const Point2 u = r / rn;
  const double t0 = (b0 - a0).dot(u);
  const double t1 = (b1 - a0).dot(u);
  return std::max(t0, t1) >= -kGeometryEpsCm && std::min(t0, t1) <= rn + kGeometryEpsCm;
}

}  // namespace

double signedArea(const Polyline& polygon) {
  double twice = 0;
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i)
    twice += cross(polygon[i], polygon[(i + 1) % n]);
  return 0.5 * twice;
}

double polygonArea(const Polyline& polygon) {
  return std::abs(signedArea(polygon));
}

double polygonPerimeter(const Polyline& polygon) {
  double total = 0;
  const size_t n = polygon.size();
  if (n < 2)
    return 0;
  for (size_t i = 0; i < n; ++i)
    total += (polygon[(i + 1) % n] - polygon[i]).norm();
  return total;
}

bool hasPositiveOrientation(const Polyline& polygon) {
  return signedArea(polygon) > 0;
}

Polyline withPositiveOrientation(const Polyline& polygon) {
  if (polygon.size() < 3 || signedArea(polygon) >= 0)
    return polygon;
  Polyline out{polygon.front()};
  out.insert(out.end(), polygon.rbegin(), polygon.rend() - 1);
  return out;
}

std::optional<std::pair<int, int>> findSelfIntersection(const Polyline& polygon) {
  const int n = int(polygon.size());
  if (n < 3)
    return std::nullopt;
  auto p = [&](int i) -> const Point2& { return polygon[size_t(i % n)]; };
  for (int i = 0; i < n; ++i) {
    if ((p(i + 1) - p(i)).norm() < kGeometryEpsCm)
      return std::make_pair(i, (i + 1) % n);
  }
  for (int i = 0; i < n; ++i) {
    // Adjacent edges share a vertex; they intersect improperly only when the second folds
    // back along the first (a zero-angle spike).
    {
      const Point2 d0 = p(i + 1) - p(i);
      const Point2 d1 = p(i + 2) - p(i + 1);
      if (std::abs(cross(d0, d1)) < kGeometryEpsCm * d0.norm() && d0.dot(d1) < 0) {
        return std::make_pair(std::min(i, (i + 1) % n), std::max(i, (i + 1) % n));
      }
    }
    const Point2 amin = p(i).cwiseMin(p(i + 1)).array() - kGeometryEpsCm;
    const Point2 amax = p(i).cwiseMax(p(i + 1)).array() + kGeometryEpsCm;
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1)
        continue;  // adjacent through the closing edge
      const Point2 bmin = p(j).cwiseMin(p(j + 1));
      const Point2 bmax = p(j).cwiseMax(p(j + 1));
      if ((bmin.array() > amax.array()).any() || (bmax.array() < amin.array()).any())
        continue;
      if (segmentsTouch(p(i), p(i + 1), p(j), p(j + 1)))
        return std::make_pair(i, j);
    }
  }
  return std::nullopt;
}

bool isSimplePolygon(const Polyline& polygon) {
  if (polygon.size() < 3)
    return false;
  if (polygonArea(polygon) < kGeometryEpsCm * kGeometryEpsCm)
    return false;
  return !findSelfIntersection(polygon);
}

bool pointInPolygon(const Point2& q, const Polyline& polygon) {
  bool inside = false;
  const size_t n = polygon.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[j];
    if ((a.y() > q.y()) != (b.y() > q.y())) {
      const double x = a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (q.x() < x)
        inside = !inside;
    }
  }
  return inside;
}

}  // namespace garmcap::drafts
