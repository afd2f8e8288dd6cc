#include "garmcap/drafts/geometry_lines.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace garmcap::drafts {

double degToRad(double degrees) {
  return degrees * kPi / 180.0;
}
double radToDeg(double radians) {
  return radians * 180.0 / kPi;
}

Point2 unitAtAngle(double angleDeg) {
  const double a = degToRad(angleDeg);
  return Point2(std::cos(a), std::sin(a));
}

double angleOfVector(const Point2& direction) {
  if (direction.norm() < kGeometryEpsCm)
    return 0.0;
  double deg = radToDeg(std::atan2(direction.y(), direction.x()));
  // atan2 returns [-180, 180]; fold -180 onto 180 so the range is (-180, 180].
  if (deg <= -180.0)
    deg += 360.0;
  return deg;
}

double angleOf(const Point2& from, const Point2& to) {
  return angleOfVector(to - from);
}

double angleBetween(const Point2& dirA, const Point2& dirB) {
  const double na = dirA.norm();
  const double nb = dirB.norm();
  if (na < kGeometryEpsCm || nb < kGeometryEpsCm)
    return 0.0;
  // atan2 of cross and dot is accurate near 0 and 180 where acos of the dot is not.
  return radToDeg(std::atan2(std::abs(cross2d(dirA, dirB)), dirA.dot(dirB)));
}

std::optional<Point2> unitVector(const Point2& v) {
  const double n = v.norm();
  if (!(n >= kGeometryEpsCm))
    return std::nullopt;
  return Point2(v / n);
}

Point2 perpendicularVector(const Point2& v) {
  return Point2(-v.y(), v.x());
}

Point2 pointAtAngle(const Point2& origin, double angleDeg, double distanceCm) {
  return origin + distanceCm * unitAtAngle(angleDeg);
}

Point2 pointToward(const Point2& from, const Point2& toward, double distanceCm) {
  const auto u = unitVector(toward - from);
  if (!u)
    return from;
  return from + distanceCm * *u;
}

Point2 pointAtFraction(const Point2& a, const Point2& b, double t) {
  return a + t * (b - a);
}

Point2 midpoint(const Point2& a, const Point2& b) {
  return 0.5 * (a + b);
}

Point2 pointPerpendicular(const Point2& a, const Point2& b, const Point2& base, double offsetCm) {
  const auto u = unitVector(b - a);
  if (!u)
    return base;
  return base + offsetCm * perpendicularVector(*u);
}

std::optional<Point2> bisectorGuide(const Point2& corner, const Point2& dirA, const Point2& dirB,
                                    double distanceCm) {
  const auto ua = unitVector(dirA);
  const auto ub = unitVector(dirB);
  if (!ua || !ub)
    return std::nullopt;
  const auto bis = unitVector(*ua + *ub);
  if (!bis)
    return std::nullopt;
  return Point2(corner + distanceCm * *bis);
}

Point2 rotateAbout(const Point2& p, const Point2& pivot, double angleDeg) {
  const double a = degToRad(angleDeg);
  const double c = std::cos(a);
  const double s = std::sin(a);
  const Point2 d = p - pivot;
  return pivot + Point2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
}

Polyline rotateAbout(const Polyline& points, const Point2& pivot, double angleDeg) {
  Polyline out;
  out.reserve(points.size());
  for (const auto& p : points)
    out.push_back(rotateAbout(p, pivot, angleDeg));
  return out;
}

Polyline translated(const Polyline& points, const Point2& offset) {
  Polyline out;
  out.reserve(points.size());
  for (const auto& p : points)
    out.push_back(p + offset);
  return out;
}

std::optional<Line> Line::through(const Point2& a, const Point2& b) {
  const auto u = unitVector(b - a);
  if (!u)
    return std::nullopt;
  return Line{a, *u};
}

Line Line::atAngle(const Point2& p, double angleDeg) {
  return Line{p, unitAtAngle(angleDeg)};
}

Point2 Line::at(double t) const {
  return origin + t * direction.normalized();
}

double Line::parameterOf(const Point2& p) const {
  return (p - origin).dot(direction.normalized());
}

Line parallelThrough(const Line& line, const Point2& p) {
  return Line{p, line.direction};
}

Line parallelAtDistance(const Line& line, double offsetCm) {
  const Point2 n = perpendicularVector(line.direction.normalized());
  return Line{line.origin + offsetCm * n, line.direction};
}

Line perpendicularThrough(const Line& line, const Point2& p) {
  return Line{p, perpendicularVector(line.direction)};
}

Point2 projectOntoLine(const Point2& p, const Line& line) {
  return line.at(line.parameterOf(p));
}

double signedDistanceToLine(const Point2& p, const Line& line) {
  const Point2 n = perpendicularVector(line.direction.normalized());
  return (p - line.origin).dot(n);
}

Point2 closestPointOnSegment(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 < kGeometryEpsCm * kGeometryEpsCm)
    return a;
  const double t = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
  return a + t * d;
}

std::optional<Point2> intersectLines(const Line& a, const Line& b) {
  const Point2 da = a.direction.normalized();
  const Point2 db = b.direction.normalized();
  const double denom = cross2d(da, db);
  // sin of the angle between the lines: below ~1e-9 rad the intersection is kilometres away
  // or undefined; a draft never wants that point.
  if (std::abs(denom) < 1e-9)
    return std::nullopt;
  const double t = cross2d(b.origin - a.origin, db) / denom;
  return Point2(a.origin + t * da);
}

std::optional<Point2> intersectSegments(const Point2& a0, const Point2& a1, const Point2& b0,
                                        const Point2& b1) {
  const Point2 r = a1 - a0;
  const Point2 s = b1 - b0;
  const double denom = cross2d(r, s);
  const double scale = r.norm() * s.norm();
  if (scale < kGeometryEpsCm * kGeometryEpsCm) {
    // A degenerate segment (a point): report it when it lies on the other segment.
    if (r.norm() < kGeometryEpsCm) {
      if ((closestPointOnSegment(a0, b0, b1) - a0).norm() < kGeometryEpsCm)
        return a0;
    } else if ((closestPointOnSegment(b0, a0, a1) - b0).norm() < kGeometryEpsCm) {
      return b0;
    }
    return std::nullopt;
  }
  if (std::abs(denom) < 1e-12 * scale)
    return std::nullopt;  // parallel or collinear
  const Point2 q = b0 - a0;
  const double t = cross2d(q, s) / denom;
  const double u = cross2d(q, r) / denom;
  // Tolerance in parameter space equivalent to kGeometryEpsCm along each segment, so that a
  // crossing exactly at an end point is not lost to rounding.
  const double et = kGeometryEpsCm / r.norm();
  const double eu = kGeometryEpsCm / s.norm();
  if (t < -et || t > 1 + et || u < -eu || u > 1 + eu)
    return std::nullopt;
  return Point2(a0 + std::clamp(t, 0.0, 1.0) * r);
}

std::vector<Point2> intersectLineCircle(const Line& line, const Point2& center, double radiusCm) {
  if (!(radiusCm >= 0))
    return {};
  const double tc = line.parameterOf(center);
  const Point2 foot = line.at(tc);
  const double d = (center - foot).norm();
  if (d > radiusCm + kGeometryEpsCm)
    return {};
  const double h2 = radiusCm * radiusCm - d * d;
  if (h2 <= kGeometryEpsCm * kGeometryEpsCm || radiusCm - d < kGeometryEpsCm)
    return {foot};
  const double h = std::sqrt(h2);
  return {line.at(tc - h), line.at(tc + h)};
}

std::vector<Point2> intersectCircles(const Point2& c0, double r0Cm, const Point2& c1, double r1Cm) {
  if (!(r0Cm >= 0) || !(r1Cm >= 0))
    return {};
  const Point2 d = c1 - c0;
  const double dist = d.norm();
  if (dist < kGeometryEpsCm)
    return {};  // concentric: none or infinitely many
  if (dist > r0Cm + r1Cm + kGeometryEpsCm)
    return {};
  if (dist < std::abs(r0Cm - r1Cm) - kGeometryEpsCm)
    return {};
  const Point2 u = d / dist;
  const double a = (r0Cm * r0Cm - r1Cm * r1Cm + dist * dist) / (2 * dist);
  const double h2 = r0Cm * r0Cm - a * a;
  const Point2 base = c0 + a * u;
  if (h2 <= kGeometryEpsCm * kGeometryEpsCm)
    return {base};
  const double h = std::sqrt(h2);
  const Point2 n = perpendicularVector(u);
  return {base + h * n, base - h * n};
}

Point2 mirrorPoint(const Point2& p, const Line& axis) {
  const Point2 foot = projectOntoLine(p, axis);
  return 2 * foot - p;
}

Polyline mirrorPolyline(const Polyline& points, const Line& axis) {
  Polyline out;
  out.reserve(points.size());
  for (const auto& p : points)
    out.push_back(mirrorPoint(p, axis));
  return out;
}

}  // namespace garmcap::drafts
