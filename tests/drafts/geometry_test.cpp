// Property and example tests of the geometry construction kernel (drafts/geometry*.h).

#include "garmcap/drafts/geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace garmcap::drafts {
namespace {

constexpr double kTol = 1e-9;

class Rng {
 public:
  explicit Rng(unsigned seed) : gen_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(gen_);
  }
  Point2 point(double range = 50) { return Point2(uniform(-range, range), uniform(-range, range)); }

 private:
  std::mt19937 gen_;
};

double distanceToPolyline(const Polyline& pl, const Point2& p) {
  return closestPoint(pl, p).distance;
}

// ---- lines -------------------------------------------------------------------------------

TEST(GeometryLines, AngleConventionIsDegreesWithPlus90DownThePage) {
  EXPECT_NEAR((unitAtAngle(0) - Point2(1, 0)).norm(), 0, kTol);
  EXPECT_NEAR((unitAtAngle(90) - Point2(0, 1)).norm(), 0, kTol);
  EXPECT_NEAR((unitAtAngle(-90) - Point2(0, -1)).norm(), 0, kTol);
  EXPECT_NEAR(angleOf(Point2(1, 1), Point2(1, 5)), 90, kTol);
  EXPECT_NEAR(angleOf(Point2(0, 0), Point2(-1, 0)), 180, kTol);
  EXPECT_NEAR(angleBetween(Point2(1, 0), Point2(0, -3)), 90, kTol);
  const Point2 p = pointAtAngle(Point2(2, 3), 30, 10);
  EXPECT_NEAR((p - Point2(2 + 10 * std::sqrt(3.0) / 2, 3 + 5)).norm(), 0, 1e-12);
}

TEST(GeometryLines, PointTowardAndPerpendicular) {
  const Point2 a(0, 0), b(10, 0);
  EXPECT_NEAR((pointToward(a, b, 3) - Point2(3, 0)).norm(), 0, kTol);
  EXPECT_NEAR((pointToward(a, b, -3) - Point2(-3, 0)).norm(), 0, kTol);
  EXPECT_NEAR((pointToward(a, a, 3) - a).norm(), 0, kTol);  // degenerate: stays put
  // +90° side of a direction pointing +x is +y (down the page).
  EXPECT_NEAR((pointPerpendicular(a, b, Point2(4, 0), 2) - Point2(4, 2)).norm(), 0, kTol);
  EXPECT_NEAR((midpoint(a, b) - Point2(5, 0)).norm(), 0, kTol);
}

TEST(GeometryLines, BisectorGuideOfRightAngleIsTheDiagonal) {
  const auto g = bisectorGuide(Point2(0, 0), Point2(1, 0), Point2(0, 1), std::sqrt(2.0));
  ASSERT_TRUE(g);
  EXPECT_NEAR((*g - Point2(1, 1)).norm(), 0, 1e-12);
  EXPECT_FALSE(bisectorGuide(Point2(0, 0), Point2(1, 0), Point2(-1, 0), 1));
}

TEST(GeometryLines, LineLineIntersectionLiesOnBothLines) {
  Rng rng(1);
  int found = 0;
  for (int k = 0; k < 500; ++k) {
    const auto a = Line::through(rng.point(), rng.point());
    const auto b = Line::through(rng.point(), rng.point());
    ASSERT_TRUE(a && b);
    const auto p = intersectLines(*a, *b);
    if (!p)
      continue;
    ++found;
    // Tolerance scales with how far the point is (nearly parallel lines meet far away).
    const double scale = 1 + p->norm();
    EXPECT_NEAR(signedDistanceToLine(*p, *a), 0, 1e-9 * scale);
    EXPECT_NEAR(signedDistanceToLine(*p, *b), 0, 1e-9 * scale);
  }
  EXPECT_GT(found, 490);
  EXPECT_FALSE(intersectLines(Line::horizontal(0), Line::horizontal(5)));
  EXPECT_FALSE(Line::through(Point2(1, 1), Point2(1, 1)));
}

TEST(GeometryLines, ParallelAndPerpendicularLines) {
  Rng rng(2);
  for (int k = 0; k < 200; ++k) {
    const auto l = Line::through(rng.point(), rng.point());
    ASSERT_TRUE(l);
    const Point2 p = rng.point();
    const Line par = parallelThrough(*l, p);
    EXPECT_NEAR(angleBetween(par.direction, l->direction), 0, 1e-7);
    EXPECT_NEAR(signedDistanceToLine(p, par), 0, 1e-9);
    const double off = rng.uniform(-20, 20);
    const Line shifted = parallelAtDistance(*l, off);
    EXPECT_NEAR(signedDistanceToLine(shifted.origin, *l), off, 1e-9);
    const Line perp = perpendicularThrough(*l, p);
    EXPECT_NEAR(angleBetween(perp.direction, l->direction), 90, 1e-9);
    const auto foot = intersectLines(perp, *l);
    ASSERT_TRUE(foot);
    EXPECT_NEAR((*foot - projectOntoLine(p, *l)).norm(), 0, 1e-8);
  }
}

TEST(GeometryLines, MirrorTwiceIsIdentityAndPreservesDistances) {
  Rng rng(3);
  for (int k = 0; k < 300; ++k) {
    const auto axis = Line::through(rng.point(), rng.point());
    ASSERT_TRUE(axis);
    const Point2 p = rng.point();
    const Point2 q = rng.point();
    const Point2 mp = mirrorPoint(p, *axis);
    EXPECT_NEAR((mirrorPoint(mp, *axis) - p).norm(), 0, 1e-9);
    EXPECT_NEAR((mirrorPoint(q, *axis) - mp).norm(), (q - p).norm(), 1e-9);
    EXPECT_NEAR(signedDistanceToLine(mp, *axis), -signedDistanceToLine(p, *axis), 1e-9);
  }
  // A mirrored polygon keeps its area and flips its orientation.
  const Polyline tri{Point2(0, 0), Point2(4, 0), Point2(0, 3)};
  const Polyline m = mirrorPolyline(tri, Line::vertical(10));
  EXPECT_NEAR(signedArea(m), -signedArea(tri), 1e-12);
}

TEST(GeometryLines, RotateAboutKeepsDistanceAndTurnsByTheAngle) {
  Rng rng(4);
  for (int k = 0; k < 200; ++k) {
    const Point2 p = rng.point(), pivot = rng.point();
    const double a = rng.uniform(-170, 170);
    const Point2 r = rotateAbout(p, pivot, a);
    EXPECT_NEAR((r - pivot).norm(), (p - pivot).norm(), 1e-9);
    if ((p - pivot).norm() > 1e-3) {
      double d = angleOf(pivot, r) - angleOf(pivot, p) - a;
      d = std::remainder(d, 360.0);
      EXPECT_NEAR(d, 0, 1e-7);
    }
    EXPECT_NEAR((rotateAbout(r, pivot, -a) - p).norm(), 0, 1e-9);
  }
  // +90 turns +x into +y (down the page).
  EXPECT_NEAR((rotateAbout(Point2(1, 0), Point2(0, 0), 90) - Point2(0, 1)).norm(), 0, 1e-12);
}

TEST(GeometryLines, LineCircleAndCircleCircle) {
  const auto hits = intersectLineCircle(Line::horizontal(0), Point2(5, 0), 3);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR((hits[0] - Point2(2, 0)).norm(), 0, kTol);  // ordered along the line
  EXPECT_NEAR((hits[1] - Point2(8, 0)).norm(), 0, kTol);
  EXPECT_EQ(intersectLineCircle(Line::horizontal(3), Point2(5, 0), 3).size(), 1u);
  EXPECT_TRUE(intersectLineCircle(Line::horizontal(4), Point2(5, 0), 3).empty());

  Rng rng(5);
  for (int k = 0; k < 300; ++k) {
    const Point2 c0 = rng.point(20), c1 = rng.point(20);
    const double r0 = rng.uniform(1, 30), r1 = rng.uniform(1, 30);
    for (const auto& p : intersectCircles(c0, r0, c1, r1)) {
      EXPECT_NEAR((p - c0).norm(), r0, 1e-6);
      EXPECT_NEAR((p - c1).norm(), r1, 1e-6);
    }
    const auto l = Line::through(rng.point(), rng.point());
    for (const auto& p : intersectLineCircle(*l, c0, r0)) {
      EXPECT_NEAR((p - c0).norm(), r0, 1e-6);
      EXPECT_NEAR(signedDistanceToLine(p, *l), 0, 1e-9);
    }
  }
  // Shoulder construction: a point on a line at a given distance from the neck point.
  const auto two = intersectCircles(Point2(0, 0), 5, Point2(8, 0), 5);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_GT(two[0].y(), 0);  // first on the +90° side of c0->c1
  EXPECT_TRUE(intersectCircles(Point2(0, 0), 1, Point2(10, 0), 1).empty());
  EXPECT_TRUE(intersectCircles(Point2(0, 0), 10, Point2(1, 0), 1).empty());
}

TEST(GeometryLines, SegmentIntersection) {
  const auto p = intersectSegments(Point2(0, 0), Point2(10, 10), Point2(0, 10), Point2(10, 0));
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p - Point2(5, 5)).norm(), 0, kTol);
  EXPECT_FALSE(intersectSegments(Point2(0, 0), Point2(1, 1), Point2(0, 10), Point2(10, 0)));
  // Touching at an end point counts.
  EXPECT_TRUE(intersectSegments(Point2(0, 0), Point2(5, 5), Point2(5, 5), Point2(10, 0)));
  EXPECT_FALSE(intersectSegments(Point2(0, 0), Point2(5, 0), Point2(6, 0), Point2(9, 0)));
}

// ---- curves ------------------------------------------------------------------------------

TEST(GeometryCurves, FlatteningErrorWithinTolerance) {
  Rng rng(6);
  for (double tol : {0.1, 0.01, 0.001}) {
    for (int k = 0; k < 25; ++k) {
      const CubicBezier c{rng.point(), rng.point(), rng.point(), rng.point()};
      const Polyline pl = flatten(c, tol);
      ASSERT_GE(pl.size(), 2u);
      EXPECT_EQ(pl.front(), c.p0);
      EXPECT_EQ(pl.back(), c.p3);
      // Every point of the exact curve is within tol of the polyline ...
      for (int i = 0; i <= 500; ++i) {
        ASSERT_LE(distanceToPolyline(pl, c.at(i / 500.0)), tol * (1 + 1e-9));
      }
      // ... and it is not needlessly fine: a 4x looser tolerance needs about half the points
      // (the count grows like 1/sqrt(tol) for a smooth curve).
      EXPECT_LE(pl.size(), 4 * flatten(c, 4 * tol).size() + 2);
    }
  }
  EXPECT_THROW(flatten(CubicBezier{}, 0.0), std::invalid_argument);
}

TEST(GeometryCurves, CurveLengthMatchesDenseSampling) {
  Rng rng(7);
  for (int k = 0; k < 30; ++k) {
    const BezierPath path{CubicBezier{rng.point(), rng.point(), rng.point(), rng.point()}};
    const double dense = polylineLength(sampleByParameter(path, 20001));
    EXPECT_NEAR(curveLength(path), dense, 1e-4 + 1e-6 * dense);
  }
  // Quarter circle approximation: the classic cubic (k = 0.5523) has length ~ pi/2 * r.
  const double kArm = 0.5522847498;
  const BezierPath quarter{
      CubicBezier{Point2(10, 0), Point2(10, 10 * kArm), Point2(10 * kArm, 10), Point2(0, 10)}};
  EXPECT_NEAR(curveLength(quarter), kPi / 2 * 10, 0.01);
}

TEST(GeometryCurves, SampleByArcLengthHasFixedCountAndEqualSpacing) {
  Rng rng(8);
  for (int count : {2, 3, 12, 24, 32}) {
    for (int k = 0; k < 10; ++k) {
      const BezierPath path =
          smoothCurve(Polyline{rng.point(), rng.point(), rng.point(), rng.point()});
      const Polyline s = sampleByArcLength(path, count);
      ASSERT_EQ(int(s.size()), count);
      EXPECT_EQ(s.front(), path.front().p0);
      EXPECT_EQ(s.back(), path.back().p3);
      // Arc length between consecutive samples, measured on the exact curve, is L/(count-1).
      const double total = curveLength(path);
      const Polyline dense = flatten(path, 1e-4);
      const auto cum = cumulativeLengths(dense);
      (void)cum;
      double prevS = 0;
      for (int i = 1; i < count; ++i) {
        const double si = closestPoint(dense, s[size_t(i)]).s;
        EXPECT_NEAR(si - prevS, total / (count - 1), 1e-3 * total + 1e-3) << "sample " << i;
        prevS = si;
      }
    }
  }
  EXPECT_THROW(sampleByArcLength(BezierPath{CubicBezier{}}, 1), std::invalid_argument);
}

TEST(GeometryCurves, SmoothCurvePassesThroughNodesWithContinuousTangent) {
  Rng rng(9);
  for (int k = 0; k < 100; ++k) {
    Polyline through;
    const int n = 2 + k % 6;
    for (int i = 0; i < n; ++i)
      through.push_back(rng.point());
    const BezierPath path = smoothCurve(through);
    ASSERT_EQ(path.size(), through.size() - 1);
    for (size_t i = 0; i < path.size(); ++i) {
      EXPECT_EQ(path[i].p0, through[i]);
      EXPECT_EQ(path[i].p3, through[i + 1]);
      // Arms are a third of the chord.
      const double chord = (through[i + 1] - through[i]).norm();
      EXPECT_NEAR((path[i].p1 - path[i].p0).norm(), chord / 3, 1e-9);
      EXPECT_NEAR((path[i].p3 - path[i].p2).norm(), chord / 3, 1e-9);
      if (i + 1 < path.size()) {  // C1 in direction at the joins
        EXPECT_NEAR(angleBetween(path[i].derivative(1), path[i + 1].derivative(0)), 0, 1e-6);
      }
    }
  }
}

TEST(GeometryCurves, FixedTangentsAreHonoured) {
  // Armhole-like curve: leaves the shoulder point straight down, arrives horizontally at the
  // underarm point (⟂ side seam).
  std::vector<CurveNode> nodes{
      {Point2(0, 0), Point2(0, 1)}, {Point2(2, 12), std::nullopt}, {Point2(8, 17), Point2(1, 0)}};
  const BezierPath path = smoothCurve(nodes);
  ASSERT_EQ(path.size(), 2u);
  EXPECT_NEAR(angleBetween(path.front().derivative(0), Point2(0, 1)), 0, 1e-9);
  EXPECT_NEAR(angleBetween(path.back().derivative(1), Point2(1, 0)), 0, 1e-9);
  // Straight guide points with free ends give a straight line.
  const BezierPath line = smoothCurve(Polyline{Point2(0, 0), Point2(5, 0), Point2(10, 0)});
  for (const auto& p : flatten(line))
    EXPECT_NEAR(p.y(), 0, 1e-12);
  EXPECT_NEAR(curveLength(line), 10, 1e-9);
}

TEST(GeometryCurves, DegenerateInputDoesNotProduceNaN) {
  const BezierPath same = smoothCurve(Polyline{Point2(1, 2), Point2(1, 2), Point2(1, 2)});
  const Polyline s = sampleByArcLength(same, 12);
  ASSERT_EQ(s.size(), 12u);
  for (const auto& p : s)
    EXPECT_TRUE(p.allFinite());
  EXPECT_EQ(curveLength(same), 0);
  EXPECT_THROW(smoothCurve(Polyline{Point2(0, 0)}), std::invalid_argument);
  // Duplicated guide points are merged, not turned into NaN tangents.
  const BezierPath dup =
      smoothCurve(Polyline{Point2(0, 0), Point2(3, 1), Point2(3, 1), Point2(6, 0)});
  EXPECT_EQ(dup.size(), 2u);
  for (const auto& p : flatten(dup))
    EXPECT_TRUE(p.allFinite());
}

// ---- polylines ---------------------------------------------------------------------------

TEST(GeometryPolyline, DivisionGivesEqualLengths) {
  Rng rng(10);
  for (int k = 0; k < 50; ++k) {
    Polyline pl;
    for (int i = 0; i < 2 + k % 9; ++i)
      pl.push_back(rng.point());
    const int parts = 1 + k % 7;
    const Polyline d = dividePolyline(pl, parts);
    ASSERT_EQ(int(d.size()), parts + 1);
    EXPECT_EQ(d.front(), pl.front());
    EXPECT_EQ(d.back(), pl.back());
    const double total = polylineLength(pl);
    for (int i = 0; i <= parts; ++i) {
      const auto c = closestPoint(pl, d[size_t(i)]);
      EXPECT_NEAR(c.distance, 0, 1e-9);
    }
    // Arc length between consecutive division points (measured along the polyline).
    for (int i = 0; i < parts; ++i) {
      const Polyline piece = subPolyline(pl, total * i / parts, total * (i + 1) / parts);
      EXPECT_NEAR(polylineLength(piece), total / parts, 1e-9 * (1 + total));
      EXPECT_NEAR((piece.front() - d[size_t(i)]).norm(), 0, 1e-9);
      EXPECT_NEAR((piece.back() - d[size_t(i + 1)]).norm(), 0, 1e-9);
    }
  }
  const Polyline seg = divideSegment(Point2(0, 0), Point2(9, 0), 3);
  ASSERT_EQ(seg.size(), 4u);
  EXPECT_NEAR((seg[1] - Point2(3, 0)).norm(), 0, kTol);
  EXPECT_THROW(dividePolyline(seg, 0), std::invalid_argument);
  EXPECT_EQ(resample(seg, 7).size(), 7u);
}

TEST(GeometryPolyline, PointAtLengthAndPathLength) {
  const Polyline l{Point2(0, 0), Point2(3, 0), Point2(3, 4)};
  EXPECT_NEAR(polylineLength(l), 7, kTol);
  EXPECT_NEAR((pointAtLength(l, 5) - Point2(3, 2)).norm(), 0, kTol);
  EXPECT_NEAR((pointAtLength(l, -1) - l.front()).norm(), 0, kTol);  // clamped
  EXPECT_NEAR((pointAtLength(l, 99) - l.back()).norm(), 0, kTol);
  EXPECT_NEAR(angleBetween(*tangentAtLength(l, 4), Point2(0, 1)), 0, kTol);
  EXPECT_NEAR(pathLength({l, Polyline{Point2(0, 0), Point2(0, 2)}}), 9, kTol);
  const auto cum = cumulativeLengths(l);
  ASSERT_EQ(cum.size(), 3u);
  EXPECT_NEAR(cum[1], 3, kTol);
  EXPECT_THROW(pointAtLength(Polyline{}, 0), std::invalid_argument);
}

TEST(GeometryPolyline, TrimAndExtend) {
  const Polyline l{Point2(0, 0), Point2(10, 0), Point2(10, 10)};
  const Polyline a = trimStart(l, 4);
  EXPECT_NEAR(polylineLength(a), 16, kTol);
  EXPECT_NEAR((a.front() - Point2(4, 0)).norm(), 0, kTol);
  const Polyline b = trimEnd(l, 15);
  EXPECT_NEAR(polylineLength(b), 5, kTol);
  EXPECT_EQ(b.size(), 2u);
  EXPECT_EQ(trimEnd(l, 50).size(), 1u);
  const Polyline e = extendEnd(l, 2.5);
  EXPECT_EQ(e.size(), l.size());
  EXPECT_NEAR((e.back() - Point2(10, 12.5)).norm(), 0, kTol);
  const Polyline s = extendStart(l, 1);
  EXPECT_NEAR((s.front() - Point2(-1, 0)).norm(), 0, kTol);
  EXPECT_NEAR(polylineLength(extendEnd(l, -3)), 17, kTol);  // negative shortens the last leg
  const Polyline j =
      joined(Polyline{Point2(0, 0), Point2(1, 0)}, Polyline{Point2(1, 0), Point2(1, 1)});
  EXPECT_EQ(j.size(), 3u);
  EXPECT_EQ(reversed(l).front(), l.back());
}

TEST(GeometryPolyline, IntersectionsLieOnBothCurves) {
  Rng rng(11);
  int total = 0;
  for (int k = 0; k < 40; ++k) {
    const Polyline a =
        flatten(smoothCurve(Polyline{rng.point(), rng.point(), rng.point(), rng.point()}), 0.01);
    const Polyline b = flatten(smoothCurve(Polyline{rng.point(), rng.point(), rng.point()}), 0.01);
    const auto hits = intersectPolylines(a, b);
    total += int(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) {
      const auto& h = hits[i];
      EXPECT_LT(distanceToPolyline(a, h.point), 1e-9);
      EXPECT_LT(distanceToPolyline(b, h.point), 1e-9);
      EXPECT_NEAR((pointAtLength(a, h.sA) - h.point).norm(), 0, 1e-7);
      EXPECT_NEAR((pointAtLength(b, h.sB) - h.point).norm(), 0, 1e-7);
      if (i > 0) {
        EXPECT_LE(hits[i - 1].sA, h.sA);
      }
    }
    const auto line = Line::through(rng.point(), rng.point());
    for (const auto& h : intersectPolylineLine(a, *line)) {
      EXPECT_NEAR(signedDistanceToLine(h.point, *line), 0, 1e-9);
      EXPECT_LT(distanceToPolyline(a, h.point), 1e-9);
      EXPECT_NEAR((line->at(h.sB) - h.point).norm(), 0, 1e-9);
    }
  }
  EXPECT_GT(total, 10);  // the random curves do cross: the assertions above were exercised
}

TEST(GeometryPolyline, CrossingAtSharedVertexReportedOnce) {
  const Polyline a{Point2(0, 0), Point2(5, 5), Point2(10, 10)};
  const Polyline b{Point2(0, 10), Point2(5, 5), Point2(10, 0)};
  EXPECT_EQ(intersectPolylines(a, b).size(), 1u);
  EXPECT_EQ(intersectPolylineLine(a, Line::horizontal(5)).size(), 1u);
  EXPECT_EQ(intersectPolylineLine(Polyline{Point2(0, 0), Point2(1, 0)}, Line::horizontal(5)).size(),
            0u);
}

TEST(GeometryPolyline, TrimAtIntersection) {
  // Hem line trimmed at the side seam.
  const Polyline hem{Point2(0, 50), Point2(30, 50)};
  const Polyline side{Point2(20, 0), Point2(22, 60)};
  const auto keep = trimAtIntersection(hem, side, true);
  ASSERT_TRUE(keep);
  const auto hit = firstIntersection(hem, side);
  ASSERT_TRUE(hit);
  EXPECT_NEAR((keep->back() - hit->point).norm(), 0, kTol);
  EXPECT_NEAR(polylineLength(*keep) + polylineLength(*trimAtIntersection(hem, side, false)),
              polylineLength(hem), 1e-9);
  EXPECT_FALSE(trimAtIntersection(hem, Polyline{Point2(40, 0), Point2(40, 60)}, true));
  const auto byLine = trimAtIntersection(hem, Line::vertical(12), false);
  ASSERT_TRUE(byLine);
  EXPECT_NEAR(polylineLength(*byLine), 18, kTol);
}

TEST(GeometryPolyline, ClosestPointIsNoFartherThanAnyVertexOrSample) {
  Rng rng(12);
  for (int k = 0; k < 100; ++k) {
    Polyline pl;
    for (int i = 0; i < 6; ++i)
      pl.push_back(rng.point());
    const Point2 p = rng.point(80);
    const auto c = closestPoint(pl, p);
    const Polyline dense = resample(pl, 2000);
    for (const auto& q : dense)
      ASSERT_LE(c.distance, (q - p).norm() + 1e-9);
    EXPECT_NEAR((pointAtLength(pl, c.s) - c.point).norm(), 0, 1e-9);
  }
}

// ---- polygons ----------------------------------------------------------------------------

TEST(GeometryPolygon, AreaOrientationAndPerimeter) {
  // In y-down coordinates this square runs right, DOWN, left: clockwise on paper.
  const Polyline sq{Point2(0, 0), Point2(2, 0), Point2(2, 2), Point2(0, 2)};
  EXPECT_NEAR(signedArea(sq), 4, kTol);
  EXPECT_TRUE(hasPositiveOrientation(sq));
  const Polyline rev = reversed(sq);
  EXPECT_NEAR(signedArea(rev), -4, kTol);
  const Polyline fixed = withPositiveOrientation(rev);
  EXPECT_NEAR(signedArea(fixed), 4, kTol);
  EXPECT_EQ(fixed.front(), rev.front());
  EXPECT_NEAR(polygonPerimeter(sq), 8, kTol);
  EXPECT_TRUE(pointInPolygon(Point2(1, 1), sq));
  EXPECT_FALSE(pointInPolygon(Point2(3, 1), sq));
}

TEST(GeometryPolygon, Simplicity) {
  const Polyline sq{Point2(0, 0), Point2(2, 0), Point2(2, 2), Point2(0, 2)};
  EXPECT_TRUE(isSimplePolygon(sq));
  const Polyline bow{Point2(0, 0), Point2(2, 2), Point2(2, 0), Point2(0, 2)};  // bow tie
  EXPECT_FALSE(isSimplePolygon(bow));
  ASSERT_TRUE(findSelfIntersection(bow));
  EXPECT_FALSE(isSimplePolygon(Polyline{Point2(0, 0), Point2(1, 0), Point2(2, 0)}));  // no area
  EXPECT_FALSE(isSimplePolygon(Polyline{Point2(0, 0), Point2(1, 0)}));
  // Repeated vertex and a spike folding back on its neighbour.
  EXPECT_FALSE(isSimplePolygon(Polyline{Point2(0, 0), Point2(2, 0), Point2(2, 0), Point2(0, 2)}));
  EXPECT_FALSE(isSimplePolygon(Polyline{Point2(0, 0), Point2(4, 0), Point2(2, 0), Point2(2, 3)}));
  // A vertex touching a non-adjacent edge.
  EXPECT_FALSE(isSimplePolygon(
      Polyline{Point2(0, 0), Point2(4, 0), Point2(4, 4), Point2(2, 0.0), Point2(0, 4)}));
  // A dart-shaped (concave) outline is simple.
  EXPECT_TRUE(isSimplePolygon(Polyline{Point2(0, 0), Point2(4, 0), Point2(5, 3), Point2(6, 0),
                                       Point2(10, 0), Point2(10, 8), Point2(0, 8)}));
  // Random star-shaped polygons (sorted by angle) are simple.
  Rng rng(13);
  for (int k = 0; k < 50; ++k) {
    Polyline star;
    const int n = 3 + k % 40;
    for (int i = 0; i < n; ++i) {
      star.push_back(pointAtAngle(Point2(0, 0), 360.0 * i / n + rng.uniform(0, 300.0 / n),
                                  rng.uniform(2, 10)));
    }
    EXPECT_TRUE(isSimplePolygon(star)) << "n=" << n;
    EXPECT_NEAR(polygonArea(star), polygonArea(mirrorPolyline(star, Line::horizontal(3))), 1e-9);
  }
}

TEST(GeometryPolygon, OffsetPolygon) {
  const Polyline sq{Point2(0, 0), Point2(2, 0), Point2(2, 2), Point2(0, 2)};
  for (const Polyline& p : {sq, reversed(sq)}) {
    const auto out = offsetPolygon(p, 1.0);
    ASSERT_TRUE(out);
    EXPECT_NEAR(polygonArea(*out), 16, 1e-9);  // (2 + 2·1)², miter corners
    EXPECT_EQ(signedArea(*out) > 0, signedArea(p) > 0);
    const auto in = offsetPolygon(p, -0.5);
    ASSERT_TRUE(in);
    EXPECT_NEAR(polygonArea(*in), 1, 1e-9);
    EXPECT_FALSE(offsetPolygon(p, -1.5));  // wider than the polygon
  }
  // A sharp spike gets bevelled: no vertex farther than miterLimit·d from the outline.
  const Polyline spike{Point2(10, 0), Point2(10, 1), Point2(0, 0.5)};
  const auto bev = offsetPolygon(spike, 0.5, 2.0);
  ASSERT_TRUE(bev);
  EXPECT_GT(bev->size(), spike.size());
  for (const auto& v : *bev)
    EXPECT_LE(closestPoint(joined(spike, {spike.front()}), v).distance, 1.0 + 1e-9);
  // A dart notch narrower than the offset cannot be offset simply.
  const Polyline dart{Point2(0, 0),  Point2(4, 0),  Point2(4.2, 5), Point2(4.4, 0),
                      Point2(10, 0), Point2(10, 8), Point2(0, 8)};
  EXPECT_TRUE(offsetPolygon(dart, 0.05));
  EXPECT_FALSE(offsetPolygon(dart, 1.0));
  EXPECT_FALSE(offsetPolygon(Polyline{Point2(0, 0), Point2(2, 2), Point2(2, 0), Point2(0, 2)}, 1));
  // Random star-shaped outlines: a small outward offset is simple, outside the outline and at
  // the offset distance from it (up to the miter limit at convex corners).
  Rng rng(14);
  for (int k = 0; k < 40; ++k) {
    Polyline star;
    const int n = 5 + k % 30;
    for (int i = 0; i < n; ++i) {
      star.push_back(pointAtAngle(Point2(0, 0), 360.0 * i / n + rng.uniform(0, 200.0 / n),
                                  rng.uniform(6, 10)));
    }
    const double d = 0.05;
    const auto out = offsetPolygon(star, d);
    ASSERT_TRUE(out) << "n=" << n;
    EXPECT_GT(polygonArea(*out), polygonArea(star));
    const Polyline ring = joined(star, {star.front()});
    for (const auto& v : *out) {
      EXPECT_FALSE(pointInPolygon(v, star));
      const double dist = closestPoint(ring, v).distance;
      EXPECT_GE(dist, d - 1e-9);
      EXPECT_LE(dist, 4 * d + 1e-9);
    }
  }
}

}  // namespace
}  // namespace garmcap::drafts
