#include "garmcap/drafts/geometry_curves.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace garmcap::drafts {

namespace {

// Arc length of one Bézier over [t0, t1]: 5-point Gauss-Legendre of |B'(t)| on kLengthSubdivisions
// uniform sub-intervals. Drafting curves are smooth and free of cusps (the arms are chord/3),
// so this is accurate to far below 1e-4 cm; a shared table keeps sampling by arc length exact
// and cheap.
constexpr int kLengthSubdivisions = 32;
constexpr std::array<double, 5> kGaussX = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                           0.5384693101056831, 0.9061798459386640};
constexpr std::array<double, 5> kGaussW = {0.2369268850561891, 0.4786286704993665,
                                           0.5688888888888889, 0.4786286704993665,
                                           0.2369268850561891};

// CubicBezier::derivative, forced inline. Same arithmetic as speedAt below.
[[gnu::always_inline]] inline Point2 derivativeAt(const CubicBezier& c, double t) {
  const double u = 1 - t;
  return 3 * u * u * (c.p1 - c.p0) + 6 * u * t * (c.p2 - c.p1) + 3 * t * t * (c.p3 - c.p2);
}

// The control-point differences of one segment, taken once: B'(t) = 3u²·d1 + 6ut·d2 + 3t²·d3.
struct Hodograph {
  double d1x, d1y, d2x, d2y, d3x, d3y;
  explicit Hodograph(const CubicBezier& c)
      : d1x(c.p1.x() - c.p0.x()),
        d1y(c.p1.y() - c.p0.y()),
        d2x(c.p2.x() - c.p1.x()),
        d2y(c.p2.y() - c.p1.y()),
        d3x(c.p3.x() - c.p2.x()),
        d3y(c.p3.y() - c.p2.y()) {}
};

// |B'(t)| in plain scalars, operation for operation what derivativeAt(c, t).norm() computes
// (the same products and sums in the same order, then sqrt(x² + y²)), so the same value; but
// the compiler can run several parameters side by side in vector registers, which it cannot
// through the Eigen expression.
[[gnu::always_inline]] inline double speedAt(const Hodograph& h, double t) {
  const double u = 1 - t;
  const double a = 3 * u * u, b = 6 * u * t, w = 3 * t * t;
  const double x = a * h.d1x + b * h.d2x + w * h.d3x;
  const double y = a * h.d1y + b * h.d2y + w * h.d3y;
  return std::sqrt(x * x + y * y);
}

// Arc length over [t0, t1] by the Gauss-Legendre rule: the five speeds first (independent,
// vectorisable), then the weighted sum in the rule's order.
double lengthBetween(const Hodograph& h, double t0, double t1) {
  const double half = 0.5 * (t1 - t0);
  const double mid = 0.5 * (t1 + t0);
  double speed[kGaussX.size()];
  for (size_t i = 0; i < kGaussX.size(); ++i)
    speed[i] = speedAt(h, mid + half * kGaussX[i]);
  double sum = 0;
  for (size_t i = 0; i < kGaussX.size(); ++i)
    sum += kGaussW[i] * speed[i];
  return sum * half;
}

using LengthTable = std::array<double, kLengthSubdivisions + 1>;

// Cumulative arc length at t = k / kLengthSubdivisions, k = 0..kLengthSubdivisions: each
// sub-interval's lengthBetween, with all 5 × 32 speeds evaluated in one vectorisable loop.
LengthTable lengthTable(const Hodograph& h) {
  constexpr size_t kNodes = kGaussX.size();
  constexpr size_t kAll = kNodes * kLengthSubdivisions;
  double half[kLengthSubdivisions], param[kAll], speed[kAll];
  for (int k = 0; k < kLengthSubdivisions; ++k) {
    const double t0 = double(k) / kLengthSubdivisions, t1 = double(k + 1) / kLengthSubdivisions;
    half[k] = 0.5 * (t1 - t0);
    const double mid = 0.5 * (t1 + t0);
    for (size_t i = 0; i < kNodes; ++i)
      param[size_t(k) * kNodes + i] = mid + half[k] * kGaussX[i];
  }
  for (size_t j = 0; j < kAll; ++j)
    speed[j] = speedAt(h, param[j]);
  LengthTable table{};
  for (int k = 0; k < kLengthSubdivisions; ++k) {
    double sum = 0;
    for (size_t i = 0; i < kNodes; ++i)
      sum += kGaussW[i] * speed[size_t(k) * kNodes + i];
    table[size_t(k) + 1] = table[size_t(k)] + sum * half[k];
  }
  return table;
}

// Parameter t at which the arc length from 0 equals s (0 <= s <= table.back()).
double parameterAtLength(const Hodograph& h, const LengthTable& table, double s) {
  if (s <= 0)
    return 0;
  if (s >= table.back())
    return 1;
  const auto it = std::upper_bound(table.begin(), table.end(), s);
  const int k = std::clamp(int(it - table.begin()) - 1, 0, kLengthSubdivisions - 1);
  double lo = double(k) / kLengthSubdivisions;
  double hi = double(k + 1) / kLengthSubdivisions;
  const double target = s - table[k];
  const double span = table[k + 1] - table[k];
  double t = span > 0 ? lo + (hi - lo) * target / span : lo;
  // Newton on L(lo, t) = target, kept inside the bracket [lo, hi] (bisection when a step
  // leaves it, e.g. where |B'| is tiny).
  const double t0 = lo;
  for (int iter = 0; iter < 30; ++iter) {
    const double f = lengthBetween(h, t0, t) - target;
    if (std::abs(f) < 1e-9)
      break;
    if (f > 0)
      hi = t;
    else
      lo = t;
    const double d = speedAt(h, t);
    double next = d > 1e-12 ? t - f / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi))
      next = 0.5 * (lo + hi);
    if (std::abs(next - t) < 1e-14)
      break;
    t = next;
  }
  return t;
}

// Largest distance of the control points p1, p2 from the chord [p0, p3]. The curve lies in
// the convex hull of its control points, so it lies within this distance of the chord, and
// (being continuous from p0 to p3) the chord lies within it of the curve as well.
double flatnessBound(const CubicBezier& c) {
  const double d1 = (c.p1 - closestPointOnSegment(c.p1, c.p0, c.p3)).norm();
  const double d2 = (c.p2 - closestPointOnSegment(c.p2, c.p0, c.p3)).norm();
  return std::max(d1, d2);
}

void flattenInto(const CubicBezier& c, double tol, int depth, Polyline& out) {
  // Depth 30 halves the parameter interval 2^30 times: only reached with non-finite input.
  if (depth >= 30 || !(flatnessBound(c) > tol)) {
    out.push_back(c.p3);
    return;
  }
  const auto [a, b] = c.split(0.5);
  flattenInto(a, tol, depth + 1, out);
  flattenInto(b, tol, depth + 1, out);
}

void requireCount(int count, const char* function) {
  if (count < 2) {
    throw std::invalid_argument(std::string(function) + ": count must be >= 2, got " +
                                std::to_string(count));
  }
}

// Tangent direction (unit) at the interior node i of the point list by the centripetal
// Catmull-Rom rule (knot spacing sqrt of chord length), which does not overshoot or loop on
// unevenly spaced guide points.
Point2 catmullRomTangent(const Point2& prev, const Point2& cur, const Point2& next) {
  const double d0 = std::sqrt((cur - prev).norm());
  const double d1 = std::sqrt((next - cur).norm());
  const Point2 m = (cur - prev) / d0 - (next - prev) / (d0 + d1) + (next - cur) / d1;
  if (auto u = unitVector(m))
    return *u;
  if (auto u = unitVector(next - prev))
    return *u;
  return *unitVector(next - cur);
}

}  // namespace

Point2 CubicBezier::at(double t) const {
  const double u = 1 - t;
  return u * u * u * p0 + 3 * u * u * t * p1 + 3 * u * t * t * p2 + t * t * t * p3;
}

Point2 CubicBezier::derivative(double t) const {
  return derivativeAt(*this, t);
}

std::pair<CubicBezier, CubicBezier> CubicBezier::split(double t) const {
  const Point2 a = pointAtFraction(p0, p1, t);
  const Point2 b = pointAtFraction(p1, p2, t);
  const Point2 c = pointAtFraction(p2, p3, t);
  const Point2 d = pointAtFraction(a, b, t);
  const Point2 e = pointAtFraction(b, c, t);
  const Point2 f = pointAtFraction(d, e, t);
  return {CubicBezier{p0, a, d, f}, CubicBezier{f, e, c, p3}};
}

CubicBezier bezierFromTangents(const Point2& a, const Point2& tangentA, const Point2& b,
                               const Point2& tangentB, double armFraction) {
  const double arm = armFraction * (b - a).norm();
  const Point2 ua = unitVector(tangentA).value_or(Point2::Zero());
  const Point2 ub = unitVector(tangentB).value_or(Point2::Zero());
  return CubicBezier{a, a + arm * ua, b - arm * ub, b};
}

BezierPath smoothCurve(const std::vector<CurveNode>& input) {
  if (input.size() < 2) {
    throw std::invalid_argument("smoothCurve: needs at least 2 nodes, got " +
                                std::to_string(input.size()));
  }
  // Merge coincident consecutive nodes: a zero-length chord has no direction.
  std::vector<CurveNode> nodes;
  for (const auto& n : input) {
    if (!nodes.empty() && (n.point - nodes.back().point).norm() < kGeometryEpsCm) {
      if (!nodes.back().tangent && n.tangent)
        nodes.back().tangent = n.tangent;
      continue;
    }
    nodes.push_back(n);
  }
  if (nodes.size() < 2) {
    // Every node at one place (an absurd body can do this): a degenerate segment keeps the
    // caller's fixed vertex counts and zero length.
    const Point2 p = nodes.front().point;
    return {CubicBezier{p, p, p, p}};
  }
  const size_t n = nodes.size();
  std::vector<std::optional<Point2>> tangent(n);
  for (size_t i = 0; i < n; ++i) {
    if (nodes[i].tangent)
      tangent[i] = unitVector(*nodes[i].tangent);
  }
  for (size_t i = 1; i + 1 < n; ++i) {
    if (!tangent[i]) {
      tangent[i] = catmullRomTangent(nodes[i - 1].point, nodes[i].point, nodes[i + 1].point);
    }
  }
  // Free end: the neighbour's tangent reflected about the end chord (the end of a parabola
  // through the two points), or the chord itself when the neighbour is free too.
  auto freeEnd = [](const Point2& chordDir, const std::optional<Point2>& neighbour) -> Point2 {
    if (!neighbour)
      return chordDir;
    const Point2 r = 2 * neighbour->dot(chordDir) * chordDir - *neighbour;
    return unitVector(r).value_or(chordDir);
  };
  if (!tangent[0]) {
    tangent[0] = freeEnd(*unitVector(nodes[1].point - nodes[0].point), tangent[1]);
  }
  if (!tangent[n - 1]) {
    tangent[n - 1] = freeEnd(*unitVector(nodes[n - 1].point - nodes[n - 2].point), tangent[n - 2]);
  }
  BezierPath path;
  path.reserve(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) {
    path.push_back(
        bezierFromTangents(nodes[i].point, *tangent[i], nodes[i + 1].point, *tangent[i + 1]));
  }
  return path;
}

BezierPath smoothCurve(const Polyline& through, std::optional<Point2> startTangent,
                       std::optional<Point2> endTangent) {
  std::vector<CurveNode> nodes;
  nodes.reserve(through.size());
  for (const auto& p : through)
    nodes.push_back(CurveNode{p, std::nullopt});
  if (!nodes.empty()) {
    nodes.front().tangent = startTangent;
    nodes.back().tangent = endTangent;
  }
  return smoothCurve(nodes);
}

Polyline flatten(const CubicBezier& curve, double toleranceCm) {
  if (!(toleranceCm > 0)) {
    throw std::invalid_argument("flatten: tolerance must be > 0 cm, got " +
                                std::to_string(toleranceCm));
  }
  Polyline out{curve.p0};
  flattenInto(curve, toleranceCm, 0, out);
  return out;
}

Polyline flatten(const BezierPath& path, double toleranceCm) {
  Polyline out;
  for (const auto& c : path) {
    Polyline part = flatten(c, toleranceCm);
    const size_t skip =
        (!out.empty() && (out.back() - part.front()).norm() < kGeometryEpsCm) ? 1 : 0;
    out.insert(out.end(), part.begin() + long(skip), part.end());
  }
  return out;
}

Polyline sampleByArcLength(const BezierPath& path, int count) {
  requireCount(count, "sampleByArcLength");
  if (path.empty())
    throw std::invalid_argument("sampleByArcLength: empty path");
  std::vector<Hodograph> hodographs;
  std::vector<LengthTable> tables;
  std::vector<double> start{0.0};  // arc length at the start of each segment
  hodographs.reserve(path.size());
  tables.reserve(path.size());
  start.reserve(path.size() + 1);
  for (const auto& c : path) {
    hodographs.emplace_back(c);
    tables.push_back(lengthTable(hodographs.back()));
    start.push_back(start.back() + tables.back().back());
  }
  const double total = start.back();
  Polyline out;
  out.reserve(size_t(count));
  size_t seg = 0;
  for (int k = 0; k < count; ++k) {
    if (k == count - 1) {
      out.push_back(path.back().p3);  // exact end point, not a rounded one
      break;
    }
    const double s = total * k / (count - 1);
    while (seg + 1 < path.size() && s > start[seg + 1])
      ++seg;
    const double t = parameterAtLength(hodographs[seg], tables[seg], s - start[seg]);
    out.push_back(path[seg].at(t));
  }
  return out;
}

Polyline sampleByParameter(const BezierPath& path, int count) {
  requireCount(count, "sampleByParameter");
  if (path.empty())
    throw std::invalid_argument("sampleByParameter: empty path");
  const double segments = double(path.size());
  Polyline out;
  out.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    const double u = segments * k / (count - 1);
    const size_t seg = std::min(size_t(u), path.size() - 1);
    out.push_back(path[seg].at(u - double(seg)));
  }
  return out;
}

double curveLength(const BezierPath& path) {
  double total = 0;
  for (const auto& c : path)
    total += lengthTable(Hodograph(c)).back();
  return total;
}

}  // namespace garmcap::drafts
