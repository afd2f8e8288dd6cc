#include "garmcap/drafts/geometry_polyline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry_polyline_cum.h"

namespace garmcap::drafts {

namespace {

void requireNonEmpty(const Polyline& pl, const char* function) {
  if (pl.empty())
    throw std::invalid_argument(std::string(function) + ": empty polyline");
}

void requireParts(int parts, const char* function) {
  if (parts < 1) {
    throw std::invalid_argument(std::string(function) + ": parts must be >= 1, got " +
                                std::to_string(parts));
  }
}

// Segment index and fraction for arc length s (clamped), given the cumulative lengths.
std::pair<size_t, double> locate(const std::vector<double>& cum, double s) {
  const size_t last = cum.size() - 1;
  if (last == 0)
    return {0, 0.0};
  s = std::clamp(s, 0.0, cum.back());
  size_t i = size_t(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
  i = std::clamp<size_t>(i, 1, last) - 1;
  // Skip zero-length segments so the fraction is well defined.
  while (i + 1 < last && cum[i + 1] - cum[i] <= 0 && s >= cum[i + 1])
    ++i;
  const double len = cum[i + 1] - cum[i];
  const double f = len > 0 ? std::clamp((s - cum[i]) / len, 0.0, 1.0) : 0.0;
  return {i, f};
}

}  // namespace

double polylineLength(const Polyline& pl) {
  double total = 0;
  for (size_t i = 1; i < pl.size(); ++i)
    total += (pl[i] - pl[i - 1]).norm();
  return total;
}

double pathLength(const std::vector<Polyline>& pieces) {
  double total = 0;
  for (const auto& p : pieces)
    total += polylineLength(p);
  return total;
}

std::vector<double> cumulativeLengths(const Polyline& pl) {
  std::vector<double> cum;
  cum.reserve(pl.size());
  for (size_t i = 0; i < pl.size(); ++i) {
    cum.push_back(i == 0 ? 0.0 : cum.back() + (pl[i] - pl[i - 1]).norm());
  }
  return cum;
}

Point2 pointAtLength(const Polyline& pl, double s) {
  requireNonEmpty(pl, "pointAtLength");
  if (pl.size() == 1)
    return pl.front();
  return detail::pointAtLength(pl, cumulativeLengths(pl), s);
}

std::optional<Point2> tangentAtLength(const Polyline& pl, double s) {
  if (pl.size() < 2)
    return std::nullopt;
  const auto cum = cumulativeLengths(pl);
  if (cum.back() <= 0)
    return std::nullopt;
  auto [i, f] = locate(cum, s);
  (void)f;
  // The segment found may have zero length; walk to the nearest one that has a direction.
  for (size_t j = i; j + 1 < pl.size(); ++j) {
    if (auto u = unitVector(pl[j + 1] - pl[j]))
      return u;
  }
  for (size_t j = i; j-- > 0;) {
    if (auto u = unitVector(pl[j + 1] - pl[j]))
      return u;
  }
  return std::nullopt;
}

Polyline divideSegment(const Point2& a, const Point2& b, int parts) {
  requireParts(parts, "divideSegment");
  Polyline out;
  out.reserve(size_t(parts) + 1);
  for (int k = 0; k <= parts; ++k)
    out.push_back(k == parts ? b : pointAtFraction(a, b, double(k) / parts));
  return out;
}

Polyline dividePolyline(const Polyline& pl, int parts) {
  requireParts(parts, "dividePolyline");
  requireNonEmpty(pl, "dividePolyline");
  const auto cum = cumulativeLengths(pl);
  Polyline out;
  out.reserve(size_t(parts) + 1);
  for (int k = 0; k <= parts; ++k) {
    if (k == parts) {
      out.push_back(pl.back());
      break;
    }
    if (pl.size() == 1) {
      out.push_back(pl.front());
      continue;
    }
    const auto [i, f] = locate(cum, cum.back() * k / parts);
    out.push_back(pointAtFraction(pl[i], pl[i + 1], f));
  }
  return out;
}

Polyline resample(const Polyline& pl, int count) {
  if (count < 2) {
    throw std::invalid_argument("resample: count must be >= 2, got " + std::to_string(count));
  }
  return dividePolyline(pl, count - 1);
}

Polyline subPolyline(const Polyline& pl, double s0, double s1) {
  requireNonEmpty(pl, "subPolyline");
  if (pl.size() == 1)
    return {pl.front()};
  return detail::subPolyline(pl, cumulativeLengths(pl), s0, s1);
}

Polyline trimStart(const Polyline& pl, double lengthCm) {
  requireNonEmpty(pl, "trimStart");
  const double total = polylineLength(pl);
  if (lengthCm >= total)
    return {pl.back()};
  return subPolyline(pl, std::max(0.0, lengthCm), total);
}

Polyline trimEnd(const Polyline& pl, double lengthCm) {
  requireNonEmpty(pl, "trimEnd");
  const double total = polylineLength(pl);
  if (lengthCm >= total)
    return {pl.front()};
  return subPolyline(pl, 0.0, total - std::max(0.0, lengthCm));
}

Polyline extendStart(const Polyline& pl, double lengthCm) {
  return reversed(extendEnd(reversed(pl), lengthCm));
}

Polyline extendEnd(const Polyline& pl, double lengthCm) {
  if (pl.size() < 2) {
    throw std::invalid_argument("extendEnd: needs a polyline of at least 2 points, got " +
                                std::to_string(pl.size()));
  }
  // Direction of the last segment that has one (trailing duplicates have none).
  for (size_t j = pl.size() - 1; j > 0; --j) {
    if (auto u = unitVector(pl[j] - pl[j - 1])) {
      Polyline out = pl;
      out.back() = pl.back() + lengthCm * *u;
      return out;
    }
  }
  return pl;  // zero length: no direction to extend along
}

Polyline reversed(const Polyline& pl) {
  return Polyline(pl.rbegin(), pl.rend());
}

Polyline joined(const Polyline& a, const Polyline& b) {
  Polyline out = a;
  const size_t skip =
      (!a.empty() && !b.empty() && (a.back() - b.front()).norm() < kGeometryEpsCm) ? 1 : 0;
  out.insert(out.end(), b.begin() + long(skip), b.end());
  return out;
}

std::vector<PolylineHit> intersectPolylineLine(const Polyline& pl, const Line& line) {
  std::vector<PolylineHit> hits;
  if (pl.size() < 2)
    return hits;
  const auto cum = cumulativeLengths(pl);
  std::vector<double> side(pl.size());
  for (size_t i = 0; i < pl.size(); ++i) {
    const double d = signedDistanceToLine(pl[i], line);
    side[i] = std::abs(d) < kGeometryEpsCm ? 0.0 : d;
  }
  for (size_t i = 0; i + 1 < pl.size(); ++i) {
    const double d0 = side[i];
    const double d1 = side[i + 1];
    if (d0 == 0 && d1 == 0)
      continue;  // collinear overlap: not a crossing
    if (d0 == 0) {
      // A vertex on the line is reported once, by the segment that starts there, unless it is
      // the end of the previous segment that was already counted.
      if (i > 0 && side[i - 1] != 0)
        continue;
      hits.push_back(PolylineHit{pl[i], cum[i], line.parameterOf(pl[i]), int(i)});
      continue;
    }
    if (d1 == 0) {
      hits.push_back(PolylineHit{pl[i + 1], cum[i + 1], line.parameterOf(pl[i + 1]), int(i)});
      continue;
    }
    if ((d0 < 0) == (d1 < 0))
      continue;
    const double f = d0 / (d0 - d1);
    const Point2 p = pointAtFraction(pl[i], pl[i + 1], f);
    hits.push_back(PolylineHit{p, cum[i] + f * (cum[i + 1] - cum[i]), line.parameterOf(p), int(i)});
  }
  return hits;
}

std::vector<PolylineHit> intersectPolylines(const Polyline& a, const Polyline& b) {
  std::vector<PolylineHit> hits;
  if (a.size() < 2 || b.size() < 2)
    return hits;
  const auto ca = cumulativeLengths(a);
  const auto cb = cumulativeLengths(b);
  for (size_t i = 0; i + 1 < a.size(); ++i) {
    // Bounding-box reject keeps this near-linear for the typical draft curve pair.
    const Point2 amin = a[i].cwiseMin(a[i + 1]).array() - kGeometryEpsCm;
    const Point2 amax = a[i].cwiseMax(a[i + 1]).array() + kGeometryEpsCm;
    for (size_t j = 0; j + 1 < b.size(); ++j) {
      const Point2 bmin = b[j].cwiseMin(b[j + 1]);
      const Point2 bmax = b[j].cwiseMax(b[j + 1]);
      if ((bmin.array() > amax.array()).any() || (bmax.array() < amin.array()).any())
        continue;
      const auto p = intersectSegments(a[i], a[i + 1], b[j], b[j + 1]);
      if (!p)
        continue;
      const double sa = ca[i] + (*p - a[i]).norm();
      const double sb = cb[j] + (*p - b[j]).norm();
      hits.push_back(PolylineHit{*p, sa, sb, int(i)});
    }
  }
  std::sort(hits.begin(), hits.end(), [](const PolylineHit& x, const PolylineHit& y) {
    return x.sA < y.sA || (x.sA == y.sA && x.sB < y.sB);
  });
  // A crossing at a shared vertex is found by up to four segment pairs: keep one.
  std::vector<PolylineHit> unique;
  for (const auto& h : hits) {
    const bool dup = std::any_of(unique.begin(), unique.end(), [&](const PolylineHit& u) {
      return std::abs(u.sA - h.sA) < 1e-5 && std::abs(u.sB - h.sB) < 1e-5;
    });
    if (!dup)
      unique.push_back(h);
  }
  return unique;
}

std::optional<PolylineHit> firstIntersection(const Polyline& pl, const Line& line) {
  // intersectPolylineLine's first hit, found by the same tests in the same order, but stopping
  // there: sides and arc lengths are computed up to the hit only (the same sums as
  // cumulativeLengths, so the same values).
  if (pl.size() < 2)
    return std::nullopt;
  auto sideOf = [&](size_t i) {
    const double d = signedDistanceToLine(pl[i], line);
    return std::abs(d) < kGeometryEpsCm ? 0.0 : d;
  };
  double before = 0;  // side of vertex i - 1 (read only when i > 0)
  double d0 = sideOf(0);
  double s0 = 0.0;
  for (size_t i = 0; i + 1 < pl.size(); ++i) {
    const double d1 = sideOf(i + 1);
    const double s1 = s0 + (pl[i + 1] - pl[i]).norm();
    if (d0 != 0 || d1 != 0) {  // both zero: collinear overlap, not a crossing
      if (d0 == 0) {
        if (!(i > 0 && before != 0))
          return PolylineHit{pl[i], s0, line.parameterOf(pl[i]), int(i)};
      } else if (d1 == 0) {
        return PolylineHit{pl[i + 1], s1, line.parameterOf(pl[i + 1]), int(i)};
      } else if ((d0 < 0) != (d1 < 0)) {
        const double f = d0 / (d0 - d1);
        const Point2 p = pointAtFraction(pl[i], pl[i + 1], f);
        return PolylineHit{p, s0 + f * (s1 - s0), line.parameterOf(p), int(i)};
      }
    }
    before = d0;
    d0 = d1;
    s0 = s1;
  }
  return std::nullopt;
}

std::optional<PolylineHit> firstIntersection(const Polyline& a, const Polyline& b) {
  auto hits = intersectPolylines(a, b);
  if (hits.empty())
    return std::nullopt;
  return hits.front();
}

namespace {

Polyline cutAt(const Polyline& pl, const PolylineHit& hit, bool keepStart) {
  // Cut by the segment index, not by arc length, so the cut point is the exact hit point.
  const size_t i = size_t(hit.segmentA);
  Polyline out;
  if (keepStart) {
    for (size_t j = 0; j <= i; ++j)
      out.push_back(pl[j]);
    if ((out.back() - hit.point).norm() >= kGeometryEpsCm || out.size() == 1)
      out.push_back(hit.point);
    else
      out.back() = hit.point;
  } else {
    out.push_back(hit.point);
    for (size_t j = i + 1; j < pl.size(); ++j) {
      if ((pl[j] - out.back()).norm() >= kGeometryEpsCm)
        out.push_back(pl[j]);
    }
    if (out.size() == 1)
      out.push_back(pl.back());
  }
  return out;
}

}  // namespace

std::optional<Polyline> trimAtIntersection(const Polyline& pl, const Polyline& cutter,
                                           bool keepStart) {
  const auto hit = firstIntersection(pl, cutter);
  if (!hit)
    return std::nullopt;
  return cutAt(pl, *hit, keepStart);
}

std::optional<Polyline> trimAtIntersection(const Polyline& pl, const Line& cutter, bool keepStart) {
  const auto hit = firstIntersection(pl, cutter);
  if (!hit)
    return std::nullopt;
  return cutAt(pl, *hit, keepStart);
}

ClosestPoint closestPoint(const Polyline& pl, const Point2& p) {
  requireNonEmpty(pl, "closestPoint");
  ClosestPoint best{pl.front(), 0.0, (p - pl.front()).norm(), 0};
  double s = 0;
  for (size_t i = 0; i + 1 < pl.size(); ++i) {
    const Point2 q = closestPointOnSegment(p, pl[i], pl[i + 1]);
    const double d = (p - q).norm();
    if (d < best.distance)
      best = ClosestPoint{q, s + (q - pl[i]).norm(), d, int(i)};
    s += (pl[i + 1] - pl[i]).norm();
  }
  return best;
}

namespace detail {

Point2 pointAtLength(const Polyline& pl, const std::vector<double>& cum, double s) {
  requireNonEmpty(pl, "pointAtLength");
  if (pl.size() == 1)
    return pl.front();
  if (s >= cum.back())
    return pl.back();
  const auto [i, f] = locate(cum, s);
  return pointAtFraction(pl[i], pl[i + 1], f);
}

Polyline subPolyline(const Polyline& pl, const std::vector<double>& cum, double s0, double s1) {
  requireNonEmpty(pl, "subPolyline");
  if (s0 > s1)
    return reversed(detail::subPolyline(pl, cum, s1, s0));
  if (pl.size() == 1)
    return {pl.front()};
  s0 = std::clamp(s0, 0.0, cum.back());
  s1 = std::clamp(s1, 0.0, cum.back());
  const auto [i0, f0] = locate(cum, s0);
  const auto [i1, f1] = locate(cum, s1);
  Polyline out{pointAtFraction(pl[i0], pl[i0 + 1], f0)};
  for (size_t j = i0 + 1; j <= i1; ++j) {
    if ((pl[j] - out.back()).norm() >= kGeometryEpsCm)
      out.push_back(pl[j]);
  }
  const Point2 end = s1 >= cum.back() ? pl.back() : pointAtFraction(pl[i1], pl[i1 + 1], f1);
  if ((end - out.back()).norm() >= kGeometryEpsCm || out.size() == 1)
    out.push_back(end);
  return out;
}

}  // namespace detail

}  // namespace garmcap::drafts
