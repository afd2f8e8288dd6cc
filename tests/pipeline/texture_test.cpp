#include "garmcap/pipeline/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

namespace {

// Fabric with horizontal stripes (period `py`) and optionally vertical ones (period `px`), bent
// the way drape bends them: every line shifted by a smooth wave along the other axis.
cv::Mat drapedFabric(cv::Size size, double py, double px, double amplitude, unsigned seed) {
  cv::Mat img(size, CV_8UC3);
  for (int r = 0; r < size.height; ++r)
    for (int c = 0; c < size.width; ++c) {
      const double yy = r + amplitude * std::sin(2 * M_PI * c / 260.0);
      const double xx = c + amplitude * std::sin(2 * M_PI * r / 300.0);
      const bool hs = py > 0 && std::fmod(yy + 1000 * py, py) < py / 2;
      const bool vs = px > 0 && std::fmod(xx + 1000 * px, px) < px / 2;
      cv::Vec3b colour(210, 215, 220);
      if (hs)
        colour = cv::Vec3b(150, 60, 30);
      if (vs)
        colour = hs ? cv::Vec3b(90, 30, 20) : cv::Vec3b(120, 40, 160);
      img.at<cv::Vec3b>(r, c) = colour;
    }
  cv::Mat noise(size, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0, 4);
  img += noise;
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
  return img;
}

cv::Mat fullMask(cv::Size size) {
  return cv::Mat(size, CV_8UC1, cv::Scalar(255));
}

// How straight the horizontal lines of an image are: the contrast of its row means relative to
// the per-pixel contrast (1 = perfectly straight lines, ~0 = lines smeared by bending).
double rowStraightness(const cv::Mat& bgr) {
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  g.convertTo(g, CV_64F);
  cv::Mat rows;
  cv::reduce(g, rows, 1, cv::REDUCE_AVG);
  cv::Scalar m, sdRows, sdAll;
  cv::meanStdDev(rows, m, sdRows);
  cv::meanStdDev(g, m, sdAll);
  return sdRows[0] / sdAll[0];
}

}  // namespace

TEST(Texture, SolidFabricGivesItsMedianColour) {
  cv::Mat img(300, 300, CV_8UC3, cv::Scalar(40, 80, 200));
  cv::Mat noise(img.size(), CV_8UC3);
  cv::RNG(3).fill(noise, cv::RNG::NORMAL, 0, 3);
  img += noise;
  const TextureResult t = extractTexture(img, fullMask(img.size()));
  EXPECT_EQ(t.kind, FabricKind::kSolid);
  EXPECT_NEAR(t.meanColour[0], 40, 3);
  EXPECT_NEAR(t.meanColour[2], 200, 3);
  EXPECT_EQ(t.tile.size(), cv::Size(64, 64));
}

TEST(Texture, BentStripesAreStraightenedAndCutToOneRepeat) {
  const double period = 24;
  const cv::Mat img = drapedFabric({420, 420}, period, 0, 7, 5);
  const TextureResult t = extractTexture(img, fullMask(img.size()));
  EXPECT_EQ(t.kind, FabricKind::kStripes);
  EXPECT_GE(t.horizontalLines, 6);
  EXPECT_NEAR(t.periodYPx, period, 0.08 * period);
  EXPECT_NEAR(t.tile.rows, period, 0.08 * period + 1);
}

TEST(Texture, StraighteningRemovesTheBend) {
  const cv::Mat img = drapedFabric({400, 400}, 20, 0, 8, 9);
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(grey, CV_32F);
  const TracedLines lines = traceHorizontalLines(grey);
  ASSERT_GE(lines.lineY.size(), 6u);
  const auto straight = straightenHorizontal(img, lines);
  ASSERT_TRUE(straight.has_value());
  EXPECT_LT(rowStraightness(img), 0.5);
  EXPECT_GT(rowStraightness(*straight), 0.8);
}

TEST(Texture, ChecksHaveBothPeriods) {
  const cv::Mat img = drapedFabric({420, 420}, 30, 26, 5, 11);
  const TextureResult t = extractTexture(img, fullMask(img.size()));
  EXPECT_EQ(t.kind, FabricKind::kChecks);
  EXPECT_NEAR(t.periodYPx, 30, 2.5);
  EXPECT_NEAR(t.periodXPx, 26, 2.5);
}

TEST(Texture, EmptyMaskIsRefused) {
  const cv::Mat img(50, 50, CV_8UC3, cv::Scalar(1, 2, 3));
  EXPECT_THROW(extractTexture(img, cv::Mat::zeros(img.size(), CV_8UC1)), std::invalid_argument);
}
