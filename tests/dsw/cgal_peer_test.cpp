// Peer check of our mean value and Wachspress coordinates against CGAL 5.5's
// Barycentric_coordinates_2 on random simple polygons, convex and concave, with queries
// inside, outside and near edges.
//
// Where CGAL is compared and where the long-double reference is used instead:
// - CGAL (policy PRECISE_WITH_EDGE_CASES, Simple_cartesian<double>) for queries at least
//   1e-3 cm from every edge's supporting line, on polygons of at most 40 vertices at cm scale
//   (its O(N²) product formula overflows near 64 vertices at mm scale), and for queries exactly
//   on vertices. Tolerance: max |weight difference| < 1e-10.
// - The long-double reference (mvc_reference.h) for queries 1e-4 to 1e-12 cm from edges,
//   where CGAL's PRECISE policy loses up to ~1e-9 and its FAST policies return NaN.
//   Tolerance: 1e-10 as well.
#include <CGAL/Barycentric_coordinates_2/Mean_value_coordinates_2.h>
#include <CGAL/Barycentric_coordinates_2/Wachspress_coordinates_2.h>
#include <CGAL/Simple_cartesian.h>
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "garmcap/dsw/mean_value_coordinates.h"
#include "garmcap/dsw/wachspress_coordinates.h"
#include "mvc_reference.h"
#include "test_polygons.h"

namespace garmcap::dsw {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using CgalPoint = Kernel::Point_2;
namespace BC = CGAL::Barycentric_coordinates;

std::vector<CgalPoint> toCgal(const Points& p) {
  std::vector<CgalPoint> out;
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    out.emplace_back(p(i, 0), p(i, 1));
  return out;
}

TEST(CgalPeer, MeanValueCoordinatesAgreeWhereCgalIsSound) {
  std::mt19937 rng(2024);
  int compared = 0;
  double worst = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 3 + trial % 38;
    const Points cage = trial % 2 ? testing::randomStar(n, rng) : testing::randomConvex(n, rng);
    const std::vector<CgalPoint> poly = toCgal(cage);
    BC::Mean_value_coordinates_2<std::vector<CgalPoint>, Kernel> cgal(
        poly, BC::Computation_policy_2::PRECISE_WITH_EDGE_CASES);
    Points pts = testing::randomPointsAround(cage, 200, rng);
    Points all(pts.rows() + cage.rows(), 2);
    all << pts, cage;  // plus every vertex exactly
    auto ours = meanValueCoordinates(cage, all);
    ASSERT_TRUE(ours.ok()) << ours.error().message;
    std::vector<double> c;
    for (Eigen::Index k = 0; k < all.rows(); ++k) {
      const bool vertex = k >= pts.rows();
      if (!vertex && testing::distanceToEdgeLines(cage, all.row(k)) < 1e-3)
        continue;
      c.clear();
      cgal(CgalPoint(all(k, 0), all(k, 1)), std::back_inserter(c));
      ASSERT_EQ(static_cast<Eigen::Index>(c.size()), cage.rows());
      for (Eigen::Index i = 0; i < cage.rows(); ++i) {
        const double diff = std::abs((*ours)(k, i) - c[static_cast<std::size_t>(i)]);
        worst = std::max(worst, diff);
        ASSERT_LT(diff, 1e-10) << "trial " << trial << " point " << k << " vertex " << i;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 10000);
  RecordProperty("worst_difference", std::to_string(worst));
}

TEST(CgalPeer, MeanValueCoordinatesMatchLongDoubleNearEdges) {
  std::mt19937 rng(77);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 3 + trial % 60;  // also beyond where CGAL's PRECISE policy is sound
    const Points cage = trial % 2 ? testing::randomStar(n, rng) : testing::randomConvex(n, rng);
    for (double d : {1e-4, 1e-6, 1e-8, 1e-10, 1e-12}) {
      const Points pts = testing::pointsNearEdges(cage, 60, d, rng);
      auto ours = meanValueCoordinates(cage, pts);
      ASSERT_TRUE(ours.ok()) << ours.error().message;
      const Eigen::MatrixXd ref = testing::referenceMvc(cage, pts);
      EXPECT_LT((*ours - ref).cwiseAbs().maxCoeff(), 1e-10) << "trial " << trial << " d " << d;
    }
  }
}

TEST(CgalPeer, WachspressCoordinatesAgreeInsideConvexPolygons) {
  std::mt19937 rng(99);
  for (int trial = 0; trial < 30; ++trial) {
    const Points cage = testing::randomConvex(3 + trial, rng);
    const std::vector<CgalPoint> poly = toCgal(cage);
    BC::Wachspress_coordinates_2<std::vector<CgalPoint>, Kernel> cgal(
        poly, BC::Computation_policy_2::PRECISE_WITH_EDGE_CASES);
    Points pts(100, 2);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 100; ++k) {
      Eigen::VectorXd w = Eigen::VectorXd::NullaryExpr(cage.rows(), [&] { return u(rng); });
      pts.row(k) = (w / w.sum()).transpose() * cage;
    }
    auto ours = wachspressCoordinates(cage, pts);
    ASSERT_TRUE(ours.ok()) << ours.error().message;
    std::vector<double> c;
    for (Eigen::Index k = 0; k < pts.rows(); ++k) {
      if (testing::distanceToEdgeLines(cage, pts.row(k)) < 1e-3)
        continue;
      c.clear();
      cgal(CgalPoint(pts(k, 0), pts(k, 1)), std::back_inserter(c));
      for (Eigen::Index i = 0; i < cage.rows(); ++i)
        ASSERT_LT(std::abs((*ours)(k, i) - c[static_cast<std::size_t>(i)]), 1e-10)
            << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace garmcap::dsw
