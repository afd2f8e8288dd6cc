// The green-screen key on scenes with a known outline: strong spill on a light subject's edges
// (tinted towards the screen's colour, luminance kept) must not eat into it, and a pixel's
// coverage is still unmixed on soft edges.
#include "garmcap/calib/chroma_key.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace garmcap::calib {
namespace {

const cv::Vec3f kScreen(60, 175, 70);

// A subject of colour `subject` (BGR) with a 4x supersampled soft outline (an ellipse), on the
// screen; spill of `strength` at the edge, decaying over `spillPx` inside, tints it towards the
// screen's colour at its own luminance (the simulator's model, capture/sim/src/sim.cpp).
cv::Mat3b sceneWithSpill(cv::Size size, cv::Vec3f subject, double strength, double spillPx,
                         cv::Mat1f& coverage) {
  cv::Mat1b big(size * 4, uchar(0));
  cv::ellipse(big, cv::Point(size.width * 2, size.height * 2),
              cv::Size(size.width * 4 / 5, size.height * 7 / 4), 0, 0, 360, cv::Scalar(255),
              cv::FILLED);
  cv::Mat1f bigF;
  big.convertTo(bigF, CV_32F, 1.0 / 255);
  cv::resize(bigF, coverage, size, 0, 0, cv::INTER_AREA);
  cv::Mat1f dist;
  cv::distanceTransform(coverage > 0.5f, dist, cv::DIST_L2, 3);
  cv::Mat3b out(size);
  cv::RNG rng(3);
  const float screenLum = (kScreen[0] + kScreen[1] + kScreen[2]) / 3;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const float a = coverage(y, x);
      cv::Vec3f c = kScreen * (1 - a) + subject * a;
      if (a > 0) {
        const float w = static_cast<float>(strength * std::exp(-dist(y, x) / spillPx)) * a;
        const float lum = (c[0] + c[1] + c[2]) / 3;
        c = c * (1 - w) + kScreen * (w * lum / screenLum);
      }
      for (int k = 0; k < 3; ++k)
        out(y, x)[k] = cv::saturate_cast<uchar>(c[k] + rng.gaussian(2.0));
    }
  return out;
}

TEST(ChromaKey, StrongSpillOnALightSubjectDoesNotEatItsEdges) {
  const cv::Size size(320, 400);
  for (const cv::Vec3f& subject : {cv::Vec3f(215, 220, 225), cv::Vec3f(170, 200, 225)}) {
    cv::Mat1f coverage;
    const cv::Mat3b img = sceneWithSpill(size, subject, 0.45, 6.0, coverage);
    const KeyResult key = keyGreenScreen(img, "spill scene");
    const double truthArea = cv::sum(coverage)[0];
    const double keyedArea = cv::sum(key.alpha)[0];
    // The outline is ~900 px long: 1 px lost all round is ~0.5 % of the area.
    EXPECT_NEAR(keyedArea / truthArea, 1.0, 0.006) << subject;
    const double iou = cv::countNonZero(key.mask & (coverage > 0.5f)) /
                       static_cast<double>(cv::countNonZero(key.mask | (coverage > 0.5f)));
    EXPECT_GT(iou, 0.99) << subject;
    // The full-resolution re-key of the outline agrees.
    cv::Mat1b band;
    cv::morphologyEx(key.mask, band, cv::MORPH_GRADIENT, cv::Mat());
    cv::dilate(band, band, cv::Mat(), cv::Point(-1, -1), 3);
    const cv::Mat1b fg = foregroundInRegion(img, key, band);
    const double bandIou = cv::countNonZero(fg & (coverage > 0.5f) & band) /
                           static_cast<double>(cv::countNonZero((fg | (coverage > 0.5f)) & band));
    EXPECT_GT(bandIou, 0.97) << subject;
  }
}

TEST(ChromaKey, ADarkSubjectIsUnmixedByGreennessAlone) {
  // No brightness to go by: a dark grey subject keys by greenness, spill or not.
  cv::Mat1f coverage;
  const cv::Mat3b img = sceneWithSpill({320, 400}, cv::Vec3f(40, 42, 45), 0.3, 6.0, coverage);
  const KeyResult key = keyGreenScreen(img, "dark scene");
  EXPECT_NEAR(cv::sum(key.alpha)[0] / cv::sum(coverage)[0], 1.0, 0.01);
}

}  // namespace
}  // namespace garmcap::calib
