#pragma once
// Open polylines: measuring, dividing, cutting, extending, intersecting (curves of a draft
// are handled as their flattened polylines; see geometry_curves.h).

#include <optional>
#include <vector>

#include "garmcap/drafts/geometry_lines.h"

namespace garmcap::drafts {

/// Total length. 0 for fewer than 2 points.
double polylineLength(const Polyline& pl);
/// Total length of several pieces measured one after the other (a seam made of curves and
/// straight lines; "path measurement").
double pathLength(const std::vector<Polyline>& pieces);
/// Arc length at every vertex: result[0] = 0, result.back() = polylineLength(pl).
std::vector<double> cumulativeLengths(const Polyline& pl);

/// Point at arc length `s` from the start, s clamped to [0, length]. Throws invalid_argument
/// on an empty polyline.
Point2 pointAtLength(const Polyline& pl, double s);
/// Unit tangent (direction of travel) at arc length `s`; std::nullopt for a zero-length line.
std::optional<Point2> tangentAtLength(const Polyline& pl, double s);

/// `parts` + 1 points dividing segment [a, b] into equal parts (parts >= 1).
Polyline divideSegment(const Point2& a, const Point2& b, int parts);
/// `parts` + 1 points dividing the polyline into parts of equal arc length (parts >= 1);
/// first/last are the polyline's ends.
Polyline dividePolyline(const Polyline& pl, int parts);
/// Exactly `count` (>= 2) points equally spaced by arc length (= dividePolyline(pl, count-1)).
Polyline resample(const Polyline& pl, int count);

/// The part between arc lengths s0 and s1 (clamped), including the cut points; reversed when
/// s0 > s1.
Polyline subPolyline(const Polyline& pl, double s0, double s1);
/// Drops the first / last `lengthCm` of arc length (shortening). Result has >= 2 points
/// unless the polyline is shorter than `lengthCm` (then the single remaining end point).
Polyline trimStart(const Polyline& pl, double lengthCm);
Polyline trimEnd(const Polyline& pl, double lengthCm);
/// Extends the first / last segment straight by `lengthCm` (lengthening); the result has the
/// same number of points (the end point moves), so fixed vertex counts are kept.
Polyline extendStart(const Polyline& pl, double lengthCm);
Polyline extendEnd(const Polyline& pl, double lengthCm);

Polyline reversed(const Polyline& pl);
/// a followed by b; when b starts where a ends (within kGeometryEpsCm) that point appears once.
Polyline joined(const Polyline& a, const Polyline& b);

/// A crossing of polyline A with a line or polyline B.
struct PolylineHit {
  Point2 point;
  double sA = 0;     // arc length along A
  double sB = 0;     // arc length along B (for a Line: Line::parameterOf(point))
  int segmentA = 0;  // index i of the segment [A[i], A[i+1]] that was hit
};

/// Every crossing of the polyline with the infinite line, ordered by sA. Collinear overlaps
/// are not reported.
std::vector<PolylineHit> intersectPolylineLine(const Polyline& pl, const Line& line);
/// Every crossing between two polylines (curve-curve, line-curve with a 2-point polyline),
/// ordered by sA; a crossing exactly at a shared vertex is reported once.
std::vector<PolylineHit> intersectPolylines(const Polyline& a, const Polyline& b);
/// First crossing along `pl` with the line / polyline; std::nullopt when none.
std::optional<PolylineHit> firstIntersection(const Polyline& pl, const Line& line);
std::optional<PolylineHit> firstIntersection(const Polyline& a, const Polyline& b);

/// Trims `pl` at its first crossing with `cutter`: keepStart keeps the part from the start to
/// the crossing, else from the crossing to the end. std::nullopt when they do not cross.
std::optional<Polyline> trimAtIntersection(const Polyline& pl, const Polyline& cutter,
                                           bool keepStart);
std::optional<Polyline> trimAtIntersection(const Polyline& pl, const Line& cutter, bool keepStart);

struct ClosestPoint {
  Point2 point;
  double s = 0;         // arc length of `point` along the polyline
  double distance = 0;  // |p - point|
  int segment = 0;      // segment index (0 for a one-point polyline)
};
/// Closest point of the polyline to `p`. Throws invalid_argument on an empty polyline.
ClosestPoint closestPoint(const Polyline& pl, const Point2& p);

}  // namespace garmcap::drafts
