#include "garmcap/drafts/geometry_polygon.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "garmcap/drafts/geometry_polyline.h"

namespace garmcap::drafts {

namespace {

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
  if (std::abs(cross2d(r, b0 - a0)) / rn > kGeometryEpsCm ||
      std::abs(cross2d(r, b1 - a0)) / rn > kGeometryEpsCm) {
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
    twice += cross2d(polygon[i], polygon[(i + 1) % n]);
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
  // Edge boxes once, not once per pair (this check runs on every panel of every draft).
  std::vector<Point2> boxMin(static_cast<size_t>(n)), boxMax(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    boxMin[size_t(j)] = p(j).cwiseMin(p(j + 1));
    boxMax[size_t(j)] = p(j).cwiseMax(p(j + 1));
  }
  // The pair of edges i < j that the loop below tests, by the same predicate: boxes within
  // kGeometryEpsCm of each other, then segmentsTouch.
  auto pairTouches = [&](int i, int j) {
    if (j < i + 2 || (i == 0 && j == n - 1))
      return false;  // adjacent, possibly through the closing edge
    const Point2 amin = boxMin[size_t(i)].array() - kGeometryEpsCm;
    const Point2 amax = boxMax[size_t(i)].array() + kGeometryEpsCm;
    const Point2& bmin = boxMin[size_t(j)];
    const Point2& bmax = boxMax[size_t(j)];
    if ((bmin.array() > amax.array()).any() || (bmax.array() < amin.array()).any())
      return false;
    return segmentsTouch(p(i), p(i + 1), p(j), p(j + 1));
  };
  auto spikeAt = [&](int i) {
    // Adjacent edges share a vertex; they intersect improperly only when the second folds
    // back along the first (a zero-angle spike).
    const Point2 d0 = p(i + 1) - p(i);
    const Point2 d1 = p(i + 2) - p(i + 1);
    return std::abs(cross2d(d0, d1)) < kGeometryEpsCm * d0.norm() && d0.dot(d1) < 0;
  };
  // The usual answer, none, without testing all n²/2 pairs: edges sorted by the left side of
  // their box, each compared with the following ones whose box starts before its own ends
  // (sweep and prune, with a margin of 2 kGeometryEpsCm, wider than the pair test's, so that no
  // pair that test would accept is skipped). Only when a spike or a touching pair turns up
  // does the full loop below run, to report the same first pair as always.
  const bool finite =
      std::all_of(polygon.begin(), polygon.end(), [](const Point2& q) { return q.allFinite(); });
  if (finite) {  // (a NaN box has no place in the order: the full loop takes it)
    bool found = false;
    for (int i = 0; i < n && !found; ++i)
      found = spikeAt(i);
    std::vector<int> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
      order[size_t(i)] = i;
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return boxMin[size_t(a)].x() < boxMin[size_t(b)].x(); });
    for (size_t a = 0; a < order.size() && !found; ++a) {
      const int e = order[a];
      const double reach = boxMax[size_t(e)].x() + 2 * kGeometryEpsCm;
      for (size_t b = a + 1; b < order.size() && boxMin[size_t(order[b])].x() <= reach; ++b) {
        const int f = order[b];
        if (pairTouches(std::min(e, f), std::max(e, f))) {
          found = true;
          break;
        }
      }
    }
    if (!found)
      return std::nullopt;
  }
  for (int i = 0; i < n; ++i) {
    // Adjacent edges share a vertex; they intersect improperly only when the second folds
    // back along the first (a zero-angle spike).
    {
      const Point2 d0 = p(i + 1) - p(i);
      const Point2 d1 = p(i + 2) - p(i + 1);
      if (std::abs(cross2d(d0, d1)) < kGeometryEpsCm * d0.norm() && d0.dot(d1) < 0) {
        return std::make_pair(std::min(i, (i + 1) % n), std::max(i, (i + 1) % n));
      }
    }
    const Point2 amin = boxMin[size_t(i)].array() - kGeometryEpsCm;
    const Point2 amax = boxMax[size_t(i)].array() + kGeometryEpsCm;
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1)
        continue;  // adjacent through the closing edge
      const Point2& bmin = boxMin[size_t(j)];
      const Point2& bmax = boxMax[size_t(j)];
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

std::optional<Polyline> offsetPolygon(const Polyline& polygon, double distanceCm,
                                      double miterLimit) {
  Polyline pts;
  for (const auto& p : polygon) {
    if (pts.empty() || (p - pts.back()).norm() >= kGeometryEpsCm)
      pts.push_back(p);
  }
  while (pts.size() > 1 && (pts.front() - pts.back()).norm() < kGeometryEpsCm)
    pts.pop_back();
  if (!isSimplePolygon(pts) || !std::isfinite(distanceCm))
    return std::nullopt;
  if (distanceCm == 0)
    return pts;
  const size_t n = pts.size();
  // perpendicularVector turns +90° (from +x toward +y); for signedArea > 0 that side of each
  // edge is the inside, so the outward normal is its opposite.
  const double outward = signedArea(pts) > 0 ? -1.0 : 1.0;
  const double d = distanceCm * outward;
  std::vector<Point2> normal(n);
  for (size_t i = 0; i < n; ++i) {
    normal[i] = perpendicularVector((pts[(i + 1) % n] - pts[i]).normalized());
  }
  const double limit = std::max(1.0, miterLimit) * std::abs(distanceCm);
  const double orientation = signedArea(pts) > 0 ? 1.0 : -1.0;
  Polyline out;
  out.reserve(n + n / 4);
  for (size_t i = 0; i < n; ++i) {
    const size_t prev = (i + n - 1) % n;
    const size_t next = (i + 1) % n;
    const Line a{pts[prev] + d * normal[prev], pts[i] - pts[prev]};
    const Line b{pts[i] + d * normal[i], pts[next] - pts[i]};
    const auto miter = intersectLines(a, b);
    // The miter grows without bound only at corners that are sharp on the side we offset
    // toward: convex corners going outward, reflex corners going inward. Corners of the other
    // kind always take the miter (their offset edges cross close to the vertex).
    const bool convex = cross2d(pts[i] - pts[prev], pts[next] - pts[i]) * orientation > 0;
    const bool sharpSide = convex == (distanceCm > 0);
    if (miter && (!sharpSide || (*miter - pts[i]).norm() <= limit)) {
      out.push_back(*miter);
    } else {
      // Bevel (for collinear edges both points coincide and one is dropped).
      out.push_back(pts[i] + d * normal[prev]);
      if ((pts[i] + d * normal[i] - out.back()).norm() >= kGeometryEpsCm) {
        out.push_back(pts[i] + d * normal[i]);
      }
    }
  }
  if (!isSimplePolygon(out))
    return std::nullopt;
  // An offset wider than a feature can still come out simple (an inset square turned half
  // round): every vertex must keep the offset distance from the original outline.
  const Polyline ring = [&] {
    Polyline r = pts;
    r.push_back(pts.front());
    return r;
  }();
  for (const auto& v : out) {
    if (closestPoint(ring, v).distance < std::abs(distanceCm) * (1 - 1e-9) - kGeometryEpsCm) {
      return std::nullopt;
    }
  }
  return out;
}

}  // namespace garmcap::drafts
