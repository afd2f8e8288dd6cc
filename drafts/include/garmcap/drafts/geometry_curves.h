#pragma once
// Curves of a draft: cubic Bézier segments and the smooth "French curve" through guide points
// that every drafting book uses (see research/drafting_blocks.md §0.1), turned into polylines
// either adaptively (chord tolerance; for drawing and measuring) or at a FIXED number of
// vertices (for DSW regions, whose vertex count must not depend on the body).

#include <optional>
#include <vector>

#include "garmcap/drafts/geometry_lines.h"

namespace garmcap::drafts {

/// Default flattening tolerance: the polyline stays within 0.1 mm of the exact curve.
inline constexpr double kDefaultChordToleranceCm = 0.01;

/// Cubic Bézier p0 (start), p1, p2 (control points), p3 (end); t in [0, 1].
struct CubicBezier {
  Point2 p0 = Point2::Zero();
  Point2 p1 = Point2::Zero();
  Point2 p2 = Point2::Zero();
  Point2 p3 = Point2::Zero();
  Point2 at(double t) const;
  Point2 derivative(double t) const;  // d/dt
  /// The two halves at parameter t (de Casteljau).
  std::pair<CubicBezier, CubicBezier> split(double t) const;
};

/// A chain of Bézier segments, each starting where the previous ends.
using BezierPath = std::vector<CubicBezier>;

/// Bézier from a to b leaving a along `tangentA` and arriving at b along `tangentB` (both
/// directions of travel, any length), with control arms `armFraction` * |b - a|.
CubicBezier bezierFromTangents(const Point2& a, const Point2& tangentA, const Point2& b,
                               const Point2& tangentB, double armFraction = 1.0 / 3.0);

/// A guide point of a smooth curve, optionally with a fixed tangent (direction of travel, any
/// length; normalised inside).
struct CurveNode {
  Point2 point;
  std::optional<Point2> tangent;
};

/// C¹ cubic Bézier chain through the nodes in order (research/drafting_blocks.md §0.1): where
/// a node's tangent is not fixed, its direction is the centripetal Catmull-Rom tangent
/// (end nodes: the neighbour's tangent reflected about the chord); every control arm is
/// chord/3 long along the unit tangent. Needs at least 2 nodes (else invalid_argument);
/// consecutive coincident nodes are merged.
BezierPath smoothCurve(const std::vector<CurveNode>& nodes);
/// Convenience: nodes without fixed tangents except optional ones at the two ends.
BezierPath smoothCurve(const Polyline& through, std::optional<Point2> startTangent = std::nullopt,
                       std::optional<Point2> endTangent = std::nullopt);

/// Adaptive flattening: every point of the exact curve is within `toleranceCm` of the
/// returned polyline (and vice versa); first and last points are the curve's end points
/// exactly; joins between segments appear once.
Polyline flatten(const CubicBezier& curve, double toleranceCm = kDefaultChordToleranceCm);
Polyline flatten(const BezierPath& path, double toleranceCm = kDefaultChordToleranceCm);

/// Exactly `count` (>= 2) points equally spaced by ARC LENGTH along the curve (error of the
/// spacing below 0.1 % of the length), first and last on the end points. The count never
/// depends on the shape: use this for DSW regions.
Polyline sampleByArcLength(const BezierPath& path, int count);
/// Exactly `count` (>= 2) points at equal steps of the path parameter (each segment gets an
/// equal share of the parameter range).
Polyline sampleByParameter(const BezierPath& path, int count);

/// Arc length of the curve (adaptive, error < 1e-4 cm).
double curveLength(const BezierPath& path);

}  // namespace garmcap::drafts
