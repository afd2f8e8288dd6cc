#pragma once
// Points, angles and straight lines (see geometry.h for the conventions: cm, y down, degrees
// with +90 pointing down the page).

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace garmcap::drafts {

using Point2 = Eigen::Vector2d;
using Polyline = std::vector<Point2>;

inline constexpr double kPi = 3.14159265358979323846;
/// Two points closer than this are the same point for the kernel (1 µm).
inline constexpr double kGeometryEpsCm = 1e-6;

/// The z component of the cross product of two plane vectors (> 0: b turns left of a, in
/// x-right/y-up terms; on the page, with y down, clockwise).
inline double cross2d(const Point2& a, const Point2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double degToRad(double degrees);
double radToDeg(double radians);

/// Unit vector at `angleDeg` (0 = +x, 90 = +y = down the page).
Point2 unitAtAngle(double angleDeg);
/// Angle of the direction from `from` to `to`, in degrees in (-180, 180]. 0 when equal points.
double angleOf(const Point2& from, const Point2& to);
/// Angle of a direction vector, in degrees in (-180, 180].
double angleOfVector(const Point2& direction);
/// Unsigned angle between two direction vectors, degrees in [0, 180].
double angleBetween(const Point2& dirA, const Point2& dirB);

/// `v` normalised; std::nullopt when |v| < kGeometryEpsCm.
std::optional<Point2> unitVector(const Point2& v);
/// `v` turned by +90° (toward +y from +x): (x, y) -> (-y, x). On paper this is clockwise.
Point2 perpendicularVector(const Point2& v);

/// Point at `distanceCm` from `origin` in the direction `angleDeg`.
Point2 pointAtAngle(const Point2& origin, double angleDeg, double distanceCm);
/// Point at `distanceCm` from `from` toward `toward` (negative: away from it). When the two
/// points coincide the result is `from`.
Point2 pointToward(const Point2& from, const Point2& toward, double distanceCm);
/// a + t (b - a): t = 0.5 is the midpoint; t outside [0, 1] extends the segment.
Point2 pointAtFraction(const Point2& a, const Point2& b, double t);
Point2 midpoint(const Point2& a, const Point2& b);
/// Point at `offsetCm` from `base`, perpendicular to the direction a->b. Positive offsets go to
/// the +90° side of a->b (for a->b pointing +x that is +y, down the page).
Point2 pointPerpendicular(const Point2& a, const Point2& b, const Point2& base, double offsetCm);
/// Point at distance `distanceCm` from `corner` along the bisector of the unit directions
/// dirA and dirB (the 45° guide of a 90° corner used for armholes, necklines, crotch curves).
/// std::nullopt when the directions are opposite (no bisector).
std::optional<Point2> bisectorGuide(const Point2& corner, const Point2& dirA, const Point2& dirB,
                                    double distanceCm);
/// `p` rotated about `pivot` by `angleDeg` (positive: from +x toward +y).
Point2 rotateAbout(const Point2& p, const Point2& pivot, double angleDeg);
Polyline rotateAbout(const Polyline& points, const Point2& pivot, double angleDeg);
Polyline translated(const Polyline& points, const Point2& offset);

/// An infinite line through `origin` with direction `direction` (not necessarily unit; never
/// zero when built by the factories below).
struct Line {
  Point2 origin = Point2::Zero();
  Point2 direction = Point2::UnitX();

  /// Line through a and b. std::nullopt when a and b coincide.
  static std::optional<Line> through(const Point2& a, const Point2& b);
  /// Line through `p` at `angleDeg`.
  static Line atAngle(const Point2& p, double angleDeg);
  static Line horizontal(double yCm) { return Line{Point2(0, yCm), Point2::UnitX()}; }
  static Line vertical(double xCm) { return Line{Point2(xCm, 0), Point2::UnitY()}; }

  /// origin + t * unit(direction): t is a signed distance along the line.
  Point2 at(double t) const;
  /// Signed distance along the line of the foot of the perpendicular from `p`.
  double parameterOf(const Point2& p) const;
};

/// Parallel to `line` through `p`.
Line parallelThrough(const Line& line, const Point2& p);
/// Parallel to `line` at `offsetCm` on the +90° side of its direction (negative: other side).
Line parallelAtDistance(const Line& line, double offsetCm);
/// Perpendicular to `line` through `p` (its direction is `line` direction turned by +90°).
Line perpendicularThrough(const Line& line, const Point2& p);

/// Foot of the perpendicular from `p` on `line`.
Point2 projectOntoLine(const Point2& p, const Line& line);
/// Signed distance from `line` to `p`: positive on the +90° side of the line direction.
double signedDistanceToLine(const Point2& p, const Line& line);
/// Closest point to `p` on segment [a, b].
Point2 closestPointOnSegment(const Point2& p, const Point2& a, const Point2& b);

/// Intersection of two infinite lines; std::nullopt when (nearly) parallel.
std::optional<Point2> intersectLines(const Line& a, const Line& b);
/// Intersection of segments [a0, a1] and [b0, b1] (end points included); std::nullopt when
/// they do not meet or are collinear-overlapping.
std::optional<Point2> intersectSegments(const Point2& a0, const Point2& a1, const Point2& b0,
                                        const Point2& b1);
/// Intersections of an infinite line with the circle (center, radius): 0, 1 (tangent) or 2
/// points, ordered by increasing Line::parameterOf.
std::vector<Point2> intersectLineCircle(const Line& line, const Point2& center, double radiusCm);
/// Intersections of two circles: 0, 1 or 2 points. With two points, the first is on the +90°
/// side of the direction c0->c1 (down the page when c1 is to the right of c0).
std::vector<Point2> intersectCircles(const Point2& c0, double r0Cm, const Point2& c1, double r1Cm);

/// Reflection of `p` across `axis`.
Point2 mirrorPoint(const Point2& p, const Line& axis);
/// Every point reflected across `axis`, order kept (a reflected polygon changes orientation).
Polyline mirrorPolyline(const Polyline& points, const Line& axis);

}  // namespace garmcap::drafts
