// Property tests of the generalized barycentric coordinates: partition of unity, linear
// precision, Lagrange property, boundary values, continuity across edges, far field, and the
// refusal of cages the methods cannot use.
#include "garmcap/dsw/coordinates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "garmcap/dsw/green_coordinates.h"
#include "garmcap/dsw/mean_value_coordinates.h"
#include "garmcap/dsw/triangle_coordinates.h"
#include "garmcap/dsw/wachspress_coordinates.h"
#include "test_polygons.h"

namespace garmcap::dsw {
namespace {

using testing::bodicePolygon;
using testing::pointsNearEdges;
using testing::randomConvex;
using testing::randomPointsAround;
using testing::randomStar;

// Checks rows sum to 1 and reproduce the points to `relTol` relative to max(|p|, cage size).
void expectAffineRows(const Eigen::MatrixXd& w, const Points& cage, const Points& pts,
                      double sumTol, double relTol, const char* what) {
  ASSERT_EQ(w.rows(), pts.rows()) << what;
  ASSERT_EQ(w.cols(), cage.rows()) << what;
  ASSERT_TRUE(w.allFinite()) << what;
  const double diag = boundingDiagonal(cage);
  const Points rep = w * cage;
  for (Eigen::Index k = 0; k < pts.rows(); ++k) {
    EXPECT_NEAR(w.row(k).sum(), 1.0, sumTol) << what << " point " << k;
    const double scale = std::max(pts.row(k).norm(), diag);
    EXPECT_LE((rep.row(k) - pts.row(k)).norm(), relTol * scale)
        << what << " point " << k << " (" << pts(k, 0) << ", " << pts(k, 1) << ")";
  }
}

Eigen::MatrixXd mvc(const Points& cage, const Points& pts) {
  auto w = meanValueCoordinates(cage, pts);
  EXPECT_TRUE(w.ok()) << (w.ok() ? "" : w.error().message);
  return w.ok() ? *w : Eigen::MatrixXd();
}

TEST(MeanValueCoordinates, PartitionOfUnityAndLinearPrecisionOnRandomPolygons) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 3 + trial % 30;
    const Points cage = trial % 2 ? randomStar(n, rng) : randomConvex(n, rng);
    const Points pts = randomPointsAround(cage, 300, rng);
    expectAffineRows(mvc(cage, pts), cage, pts, 1e-12, 1e-9, "mvc random");
    // Near edges, inside and outside, down to 1e-12 cm.
    for (double d : {1e-3, 1e-6, 1e-9, 1e-12}) {
      const Points near = pointsNearEdges(cage, 50, d, rng);
      expectAffineRows(mvc(cage, near), cage, near, 1e-12, 1e-9, "mvc near edge");
    }
  }
}

TEST(MeanValueCoordinates, LagrangeAtVerticesAndSegmentCoordinatesOnEdges) {
  const Points cage = bodicePolygon();
  const Eigen::MatrixXd atVertices = mvc(cage, cage);
  EXPECT_EQ(atVertices, Eigen::MatrixXd::Identity(7, 7));
  Points onEdges(3, 2);
  onEdges << 12, 0, 24, 7.5, 13, 26;  // bottom edge middle; right edge quarter; reflex edge middle
  const Eigen::MatrixXd w = mvc(cage, onEdges);
  EXPECT_DOUBLE_EQ(w(0, 0), 0.5);
  EXPECT_DOUBLE_EQ(w(0, 1), 0.5);
  EXPECT_DOUBLE_EQ(w(1, 1), 0.75);
  EXPECT_DOUBLE_EQ(w(1, 2), 0.25);
  EXPECT_NEAR(w(2, 3), 0.5, 1e-15);
  EXPECT_NEAR(w(2, 4), 0.5, 1e-15);
  EXPECT_EQ(w.row(0).cwiseAbs().sum(), 1.0);  // nothing else
}

TEST(MeanValueCoordinates, ContinuousAcrossEdges) {
  std::mt19937 rng(7);
  const Points cage = randomStar(12, rng);
  for (Eigen::Index i = 0; i < cage.rows(); ++i) {
    const Eigen::RowVector2d a = cage.row(i), b = cage.row((i + 1) % cage.rows());
    const Eigen::RowVector2d mid = 0.37 * a + 0.63 * b;
    const Eigen::RowVector2d dir = (b - a).normalized();
    const Eigen::RowVector2d normal(-dir.y(), dir.x());
    Points q(3, 2);
    q.row(0) = mid;
    q.row(1) = mid + 1e-9 * normal;
    q.row(2) = mid - 1e-9 * normal;
    const Eigen::MatrixXd w = mvc(cage, q);
    EXPECT_LT((w.row(1) - w.row(0)).cwiseAbs().maxCoeff(), 1e-6) << "edge " << i;
    EXPECT_LT((w.row(2) - w.row(0)).cwiseAbs().maxCoeff(), 1e-6) << "edge " << i;
  }
}

TEST(MeanValueCoordinates, FarOutsideStaysFiniteAndAffine) {
  // Outside, Σw cancels to second order in (cage size / distance), so the relative
  // reproduction error grows like 1e-16·(distance/size)²: 1e-9 holds to ~1000 cage sizes
  // (a 60 cm draft: 600 m); beyond, rows stay finite and sum to 1 (docs/dsw.md).
  std::mt19937 rng(3);
  const Points cage = randomStar(20, rng);  // about 60 cm across
  Points far(4, 2);
  far << 1e3, 3e2, -2e4, 1e4, 3e4, -2e4, 0, -5e4;
  expectAffineRows(mvc(cage, far), cage, far, 1e-12, 1e-9, "mvc far");
  Points veryFar(3, 2);
  veryFar << 5e6, -5e6, 0, 1e9, -1e12, 3;
  const Eigen::MatrixXd w = mvc(cage, veryFar);
  ASSERT_TRUE(w.allFinite());
  // The coordinates themselves grow like distance/size, so the sum carries their rounding.
  for (Eigen::Index k = 0; k < w.rows(); ++k)
    EXPECT_NEAR(w.row(k).sum(), 1.0, 1e-12 * std::max(1.0, w.row(k).cwiseAbs().maxCoeff()) * 1e4);
}

TEST(MeanValueCoordinates, AffineDraftChangeMapsPointsAffinely) {
  // Linear precision means a draft that changes by an affine map moves every encoded point
  // by that map, inside and outside: the property DSW grading rests on.
  std::mt19937 rng(11);
  const Points cage = bodicePolygon();
  const Points pts = randomPointsAround(cage, 500, rng);
  Eigen::Matrix2d a;
  a << 1.1, 0.05, -0.02, 0.97;
  const Eigen::RowVector2d shift(3, -1);
  const Points target = (cage * a.transpose()).rowwise() + shift;
  const Points decoded = mvc(cage, pts) * target;
  const Points expected = (pts * a.transpose()).rowwise() + shift;
  EXPECT_LT((decoded - expected).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(MeanValueCoordinates, RepeatedVerticesSplitTheWeightAndStillReproduce) {
  Points cage(5, 2);
  cage << 0, 0, 10, 0, 10, 0, 10, 10, 0, 10;
  Points pts(3, 2);
  pts << 3, 4, 10, 0, 20, 5;
  const Eigen::MatrixXd w = mvc(cage, pts);
  expectAffineRows(w, cage, pts, 1e-12, 1e-12, "repeated vertex");
  EXPECT_EQ(w(1, 1) + w(1, 2), 1.0);
}

TEST(MeanValueCoordinates, RefusesBadCagesAndPointsWithNamedErrors) {
  Points pts(1, 2);
  pts << 1, 1;
  Points collinear(4, 2);
  collinear << 0, 0, 1, 1, 2, 2, 3, 3;
  auto r1 = meanValueCoordinates(collinear, pts);
  ASSERT_FALSE(r1.ok());
  EXPECT_NE(r1.error().message.find("zero area"), std::string::npos) << r1.error().message;
  Points bowtie(5, 2);
  bowtie << 0, 0, 4, 0, 4, 4, 2, -1, 0, 4;
  auto r2 = meanValueCoordinates(bowtie, pts);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().message.find("not simple"), std::string::npos) << r2.error().message;
  Points two(3, 2);
  two << 0, 0, 0, 0, 1, 1;
  auto r3 = meanValueCoordinates(two, pts);
  ASSERT_FALSE(r3.ok());
  EXPECT_NE(r3.error().message.find("distinct"), std::string::npos) << r3.error().message;
  Points nanCage = bodicePolygon();
  nanCage(3, 1) = std::numeric_limits<double>::quiet_NaN();
  auto r4 = meanValueCoordinates(nanCage, pts);
  ASSERT_FALSE(r4.ok());
  EXPECT_NE(r4.error().message.find("vertex 3"), std::string::npos) << r4.error().message;
  Points nanPts(2, 2);
  nanPts << 1, 1, std::numeric_limits<double>::infinity(), 0;
  auto r5 = meanValueCoordinates(bodicePolygon(), nanPts);
  ASSERT_FALSE(r5.ok());
  EXPECT_NE(r5.error().message.find("point 1"), std::string::npos) << r5.error().message;
}

TEST(MeanValueCoordinates, TinyOffsetsFromVerticesGiveNoNaN) {
  // CGAL's own special-points test: offsets of 1e-300 are exactly on the feature in double.
  const Points cage = bodicePolygon();
  Points q(cage.rows() * 2, 2);
  for (Eigen::Index i = 0; i < cage.rows(); ++i) {
    q.row(2 * i) = cage.row(i) + Eigen::RowVector2d(1e-300, 0);
    q.row(2 * i + 1) = cage.row(i) + Eigen::RowVector2d(1e-13, -1e-13);
  }
  expectAffineRows(mvc(cage, q), cage, q, 1e-12, 1e-12, "near vertex");
}

TEST(WachspressCoordinates, PropertiesOnConvexPolygons) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Points cage = randomConvex(3 + trial, rng);
    // Inside: shrink random box points toward the centroid until inside is not needed: use
    // convex combinations of vertices, which are inside.
    Points pts(200, 2);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 200; ++k) {
      Eigen::VectorXd c =
          Eigen::VectorXd::NullaryExpr(cage.rows(), [&] { return std::pow(u(rng), 4); });
      c /= c.sum();
      pts.row(k) = c.transpose() * cage;
    }
    auto w = wachspressCoordinates(cage, pts);
    ASSERT_TRUE(w.ok()) << w.error().message;
    expectAffineRows(*w, cage, pts, 1e-12, 1e-9, "wachspress");
    EXPECT_GE(w->minCoeff(), -1e-12);  // positive inside a convex polygon
    auto atVertices = wachspressCoordinates(cage, cage);
    ASSERT_TRUE(atVertices.ok());
    EXPECT_LT(
        (*atVertices - Eigen::MatrixXd::Identity(cage.rows(), cage.rows())).cwiseAbs().maxCoeff(),
        1e-15);
    const Points near = pointsNearEdges(cage, 50, 1e-9, rng);
    auto wn = wachspressCoordinates(cage, near);
    ASSERT_TRUE(wn.ok()) << wn.error().message;
    expectAffineRows(*wn, cage, near, 1e-9, 1e-9, "wachspress near edge");
  }
}

TEST(WachspressCoordinates, RefusesConcavePolygons) {
  Points pts(1, 2);
  pts << 5, 5;
  auto w = wachspressCoordinates(bodicePolygon(), pts);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().message.find("not convex"), std::string::npos);
}

TEST(GreenCoordinates, ReproduceInsideAndSimilarityInvariance) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 10; ++trial) {
    const Points cage = trial % 2 ? randomStar(8 + trial, rng) : bodicePolygon();
    // Interior points: the polygon's vertices pulled 20% toward a kernel point are not always
    // inside for a star; use points near edges on the inner side and test with the MVC sign.
    Points pts = randomPointsAround(cage, 400, rng, 0.0);
    auto gc = greenCoordinates(cage, pts);
    ASSERT_TRUE(gc.ok()) << gc.error().message;
    const Points same = *greenDecode(*gc, cage);
    Eigen::Matrix2d rot;
    const double a = 0.3 + trial;
    rot << 1.3 * std::cos(a), -1.3 * std::sin(a), 1.3 * std::sin(a), 1.3 * std::cos(a);
    const Eigen::RowVector2d shift(4, -2);
    const Points moved = *greenDecode(*gc, (cage * rot.transpose()).rowwise() + shift);
    for (Eigen::Index k = 0; k < pts.rows(); ++k) {
      const double sumPhi = gc->vertexWeights.row(k).sum();
      if (sumPhi > 0.5) {  // inside
        EXPECT_NEAR(sumPhi, 1.0, 1e-12);
        EXPECT_LT((same.row(k) - pts.row(k)).norm(), 1e-9);
        const Eigen::RowVector2d expect = pts.row(k) * rot.transpose() + shift;
        EXPECT_LT((moved.row(k) - expect).norm(), 1e-9);
      } else {  // outside: the exterior collapse that makes Green coordinates unfit for grading
        EXPECT_NEAR(sumPhi, 0.0, 1e-12);
      }
    }
  }
}

TEST(GreenCoordinates, BoundaryValuesAreTheInteriorLimit) {
  const Points cage = bodicePolygon();  // positive area: interior is to the left of edges
  Points q(4, 2);
  q << 12, 0, 24, 7.5, 0, 0, 12, 22;
  Points inside(4, 2);
  inside << 12, 1e-9, 24 - 1e-9, 7.5, 1e-9, 1e-9, 12, 22 - 1e-9;
  auto gb = greenCoordinates(cage, q);
  auto gi = greenCoordinates(cage, inside);
  ASSERT_TRUE(gb.ok() && gi.ok());
  EXPECT_TRUE(gb->vertexWeights.allFinite() && gb->edgeWeights.allFinite());
  EXPECT_LT((gb->vertexWeights - gi->vertexWeights).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((gb->edgeWeights - gi->edgeWeights).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((*greenDecode(*gb, cage) - q).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(TriangleCoordinates, TriangulationAndProperties) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    const Points cage = trial % 2 ? randomStar(4 + trial, rng) : randomConvex(4 + trial, rng);
    auto tris = triangulatePolygon(cage);
    ASSERT_TRUE(tris.ok()) << tris.error().message;
    EXPECT_EQ(static_cast<Eigen::Index>(tris->size()), cage.rows() - 2);
    double area = 0;
    for (const auto& t : *tris) {
      Points tri(3, 2);
      tri << cage.row(t[0]), cage.row(t[1]), cage.row(t[2]);
      area += twiceSignedArea(tri);
    }
    EXPECT_NEAR(area, twiceSignedArea(cage), 1e-9 * std::abs(twiceSignedArea(cage)));
    const Points pts = randomPointsAround(cage, 200, rng);
    auto w = triangleCoordinates(cage, pts);
    ASSERT_TRUE(w.ok());
    expectAffineRows(*w, cage, pts, 1e-12, 1e-9, "tbc");
    auto atVertices = triangleCoordinates(cage, cage);
    EXPECT_LT(
        (*atVertices - Eigen::MatrixXd::Identity(cage.rows(), cage.rows())).cwiseAbs().maxCoeff(),
        1e-12);
  }
}

TEST(Coordinates, EncodeDecodeEveryMethodOnAConvexCage) {
  std::mt19937 rng(17);
  const Points cage = randomConvex(9, rng);
  Points pts(100, 2);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 100; ++k) {
    Eigen::VectorXd c = Eigen::VectorXd::NullaryExpr(cage.rows(), [&] { return u(rng); });
    pts.row(k) = (c / c.sum()).transpose() * cage;
  }
  for (auto method : {CoordMethod::kMeanValue, CoordMethod::kWachspress, CoordMethod::kGreen,
                      CoordMethod::kTriangle}) {
    auto enc = encodePoints(method, cage, pts);
    ASSERT_TRUE(enc.ok()) << coordMethodName(method) << ": " << enc.error().message;
    auto dec = decodePoints(*enc, cage);
    ASSERT_TRUE(dec.ok());
    EXPECT_LT((*dec - pts).cwiseAbs().maxCoeff(), 1e-9) << coordMethodName(method);
    EXPECT_EQ(parseCoordMethod(coordMethodName(method)), method);
  }
  EXPECT_FALSE(parseCoordMethod("mean").has_value());
  auto enc = encodePoints(CoordMethod::kMeanValue, cage, pts);
  Points wrong(4, 2);
  wrong.setZero();
  EXPECT_FALSE(decodePoints(*enc, wrong).ok());
}

}  // namespace
}  // namespace garmcap::dsw
