// The measurer's section perimeters against a second implementation: the convex hull of a finely
// sampled ellipse (and a fin's tip) taken by OpenCV and measured edge by edge.
#include "garmcap/pipeline/section_perimeter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace garmcap::pipeline {
namespace {

// Perimeter of the convex hull of an ellipse (full width w, depth d) sampled at n points, with a
// fin's tip f beyond its right end when f > 0.
double sampledHullPerimeter(double w, double d, double f, int n = 20000) {
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    pts.emplace_back(0.5 * w * std::cos(t), 0.5 * d * std::sin(t));
  }
  if (f > 0)
    pts.emplace_back(0.5 * w + f, 0.0);
  // OpenCV's hull takes float points; its indices pick the double ones to measure.
  std::vector<cv::Point2f> pf(pts.begin(), pts.end());
  std::vector<int> hull;
  cv::convexHull(pf, hull);
  double p = 0;
  for (std::size_t i = 0; i < hull.size(); ++i)
    p += cv::norm(pts[static_cast<std::size_t>(hull[i])] -
                  pts[static_cast<std::size_t>(hull[(i + 1) % hull.size()])]);
  return p;
}

TEST(SectionPerimeter, EllipseMatchesASampledOne) {
  for (const auto& [w, d] : {std::pair{33.6, 26.3}, {40.0, 20.0}, {30.0, 30.0}, {12.0, 9.5}})
    EXPECT_NEAR(ellipsePerimeter(w, d), sampledHullPerimeter(w, d, 0), 1e-3 * w) << w << " x " << d;
}

TEST(SectionPerimeter, FinGainMatchesTheSampledHull) {
  for (const auto& [w, d] : {std::pair{33.6, 26.3}, {35.6, 27.3}, {30.0, 30.0}, {40.0, 22.0}})
    for (const double f : {0.2, 0.5, 1.0, 2.5, 5.0, 10.0}) {
      const double hull = sampledHullPerimeter(w, d, f) - sampledHullPerimeter(w, d, 0);
      EXPECT_NEAR(finHullGain(w, d, f), hull, 2e-3) << w << " x " << d << " fin " << f;
    }
}

TEST(SectionPerimeter, FinGainOfACircleIsItsTangentsLessTheirArc) {
  const double r = 15.0;
  for (const double f : {0.5, 3.0, 12.0}) {
    const double analytic =
        2 * std::sqrt((r + f) * (r + f) - r * r) - 2 * r * std::acos(r / (r + f));
    EXPECT_NEAR(finHullGain(2 * r, 2 * r, f), analytic, 1e-6) << f;
  }
}

// A fin adds less round than it adds width (2 f, as a segment across would), more as it grows,
// and nothing when it has no length.
TEST(SectionPerimeter, FinGainIsBelowTwiceItsLengthAndGrowsWithIt) {
  EXPECT_EQ(finHullGain(33.6, 26.3, 0.0), 0.0);
  EXPECT_EQ(finHullGain(33.6, 26.3, -1.0), 0.0);
  EXPECT_EQ(finHullGain(0.0, 26.3, 1.0), 0.0);
  double last = 0;
  for (double f = 0.25; f <= 20; f += 0.25) {
    const double g = finHullGain(33.6, 26.3, f);
    EXPECT_GT(g, last) << f;
    EXPECT_LT(g, 2 * f) << f;
    last = g;
  }
}

}  // namespace
}  // namespace garmcap::pipeline
