// Garment colours on painted garments: a plain colour under shading and folds keeps one name
// and is no print; dots and stripes are prints with both colours named. The garments are drawn
// here with OpenCV primitives and share nothing with the palette code.
#include "garmcap/daemon/garment_colour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace garmcap::daemon {
namespace {

struct Scene {
  cv::Mat3b bgr;
  cv::Mat1b mask;
};

// A skirt-like trapezoid on a green screen, lit from the left, with soft vertical folds.
Scene painted(const cv::Vec3b& base, double foldDepth) {
  Scene s{cv::Mat3b(360, 300, cv::Vec3b(40, 170, 40)), cv::Mat1b::zeros(360, 300)};
  const std::vector<cv::Point> outline = {{110, 30}, {190, 30}, {250, 330}, {50, 330}};
  cv::fillPoly(s.mask, std::vector<std::vector<cv::Point>>{outline}, 255);
  for (int y = 0; y < s.bgr.rows; ++y)
    for (int x = 0; x < s.bgr.cols; ++x) {
      if (!s.mask(y, x))
        continue;
      const double light = 1.05 - 0.2 * x / 300.0 - foldDepth * 0.5 * (1 + std::sin(x / 7.0));
      for (int c = 0; c < 3; ++c)
        s.bgr(y, x)[c] = cv::saturate_cast<uchar>(base[c] * light);
    }
  return s;
}

void blur(Scene& s) {
  cv::GaussianBlur(s.bgr, s.bgr, cv::Size(3, 3), 0.8);
}

TEST(GarmentColours, PlainColoursUnderShadingKeepOneName) {
  const std::vector<std::pair<cv::Vec3b, std::string>> cases = {
      {cv::Vec3b(84, 36, 26), "Navy"},     {cv::Vec3b(30, 30, 190), "Red"},
      {cv::Vec3b(160, 198, 220), "Beige"}, {cv::Vec3b(24, 22, 22), "Black"},
      {cv::Vec3b(240, 242, 242), "White"}, {cv::Vec3b(44, 110, 112), "Olive"}};
  for (const auto& [bgr, name] : cases) {
    Scene s = painted(bgr, 0.15);
    blur(s);
    const GarmentColours c = garmentColours(s.bgr, s.mask);
    ASSERT_FALSE(c.colours.empty()) << name;
    EXPECT_EQ(c.colours[0].name, name);
    EXPECT_GT(c.colours[0].share, 0.8) << name;
    EXPECT_FALSE(c.printed) << name;
    EXPECT_EQ(c.label(), name);
  }
}

TEST(GarmentColours, DotsAndStripesArePrints) {
  Scene dots = painted(cv::Vec3b(30, 30, 190), 0.05);
  for (int y = 40; y < 330; y += 16)
    for (int x = 60; x < 250; x += 16)
      if (dots.mask(y, x))
        cv::circle(dots.bgr, {x, y}, 4, cv::Scalar(240, 240, 240), cv::FILLED, cv::LINE_AA);
  blur(dots);
  const GarmentColours d = garmentColours(dots.bgr, dots.mask);
  EXPECT_TRUE(d.printed);
  ASSERT_GE(d.colours.size(), 2u);
  EXPECT_EQ(d.colours[0].name, "Red");
  EXPECT_EQ(d.colours[1].name, "White");
  EXPECT_EQ(d.label(), "Red/White");

  Scene stripes = painted(cv::Vec3b(84, 36, 26), 0.05);
  for (int y = 0; y < stripes.bgr.rows; ++y)
    if ((y / 8) % 2)
      for (int x = 0; x < stripes.bgr.cols; ++x)
        if (stripes.mask(y, x))
          stripes.bgr(y, x) = cv::Vec3b(238, 240, 240);
  blur(stripes);
  const GarmentColours st = garmentColours(stripes.bgr, stripes.mask);
  EXPECT_TRUE(st.printed);
  EXPECT_EQ(st.label(), "Navy/White");
}

// Rig case_002's fabric as the simulator paints it: navy with light-blue dots of a few pixels,
// about 23 ΔE from the ground (20-35 on the rig) and covering a tenth of it. The old rule (pixel
// pairs 4 px apart more than 30 ΔE apart) read it as solid.
TEST(GarmentColours, SparseLowContrastDotsAreAPrint) {
  Scene s = painted(cv::Vec3b(89, 31, 20), 0.1);
  cv::RNG rng(17);
  for (int y = 36; y < 330; y += 14)
    for (int x = 50; x < 260; x += 14) {
      const cv::Point c(x + rng.uniform(-4, 5), y + rng.uniform(-4, 5));
      if (s.mask(c.y, c.x))
        cv::circle(s.bgr, c, rng.uniform(2, 4), cv::Scalar(120, 75, 50), cv::FILLED, cv::LINE_AA);
    }
  blur(s);
  const GarmentColours c = garmentColours(s.bgr, s.mask);
  EXPECT_TRUE(c.printed) << c.printShare;
  ASSERT_FALSE(c.colours.empty());
  EXPECT_EQ(c.colours[0].name, "Navy");
}

// Deep folds and a few sharp creases (thin dark lines) on plain cloth are shading, not a print.
TEST(GarmentColours, DeepFoldsAndCreasesStaySolid) {
  for (const cv::Vec3b& base : {cv::Vec3b(84, 36, 26), cv::Vec3b(160, 198, 220),
                                cv::Vec3b(240, 242, 242), cv::Vec3b(30, 30, 190)}) {
    Scene s = painted(base, 0.3);
    for (int x : {100, 140, 175, 205}) {
      const cv::Vec3b dark(static_cast<uchar>(base[0] * 0.55), static_cast<uchar>(base[1] * 0.55),
                           static_cast<uchar>(base[2] * 0.55));
      for (int y = 0; y < s.bgr.rows; ++y)
        for (int dx = 0; dx < 2; ++dx)
          if (s.mask(y, x + dx))
            s.bgr(y, x + dx) = dark;
    }
    blur(s);
    const GarmentColours c = garmentColours(s.bgr, s.mask);
    EXPECT_FALSE(c.printed) << base << " print share " << c.printShare;
  }
}

TEST(GarmentColours, TwoColourBlocksAreNotAPrint) {
  Scene s = painted(cv::Vec3b(84, 36, 26), 0.05);
  for (int y = 180; y < s.bgr.rows; ++y)
    for (int x = 0; x < s.bgr.cols; ++x)
      if (s.mask(y, x))
        s.bgr(y, x) = cv::Vec3b(240, 242, 242);
  blur(s);
  const GarmentColours c = garmentColours(s.bgr, s.mask);
  EXPECT_FALSE(c.printed);
  EXPECT_EQ(c.colours.size(), 2u);
}

// Deeper shading than PlainColoursUnderShadingKeepOneName's: lit from above, the cloth darkens
// smoothly to 0.6 of its colour at the hem, so its lower half falls to the palette's darker name
// (Blue to Navy, Purple to Navy, Cream to Beige). It is one cloth and keeps its lit name.
TEST(GarmentColours, OneClothShadedAcrossTwoNamesKeepsOne) {
  const std::vector<std::pair<cv::Vec3b, std::string>> cases = {
      {cv::Vec3b(196, 104, 74), "Blue"},
      {cv::Vec3b(146, 90, 146), "Purple"},
      {cv::Vec3b(214, 248, 250), "Cream"}};
  for (const auto& [bgr, name] : cases) {
    Scene s = painted(bgr, 0.0);
    for (int y = 0; y < s.bgr.rows; ++y)
      for (int x = 0; x < s.bgr.cols; ++x)
        if (s.mask(y, x))
          for (int c = 0; c < 3; ++c)
            s.bgr(y, x)[c] = cv::saturate_cast<uchar>(bgr[c] * (1.0 - 0.4 * y / s.bgr.rows));
    blur(s);
    const GarmentColours c = garmentColours(s.bgr, s.mask);
    EXPECT_EQ(c.label(), name);
    EXPECT_FALSE(c.printed) << name;
  }
}

// Two cloths of one hue, one much darker than shading makes (navy beside blue, 2.3 times as
// bright; grey beside black) stay two colours.
TEST(GarmentColours, TwoShadesOfOneHueAsBlocksStayTwo) {
  const std::vector<std::pair<cv::Vec3b, cv::Vec3b>> cases = {
      {cv::Vec3b(84, 36, 26), cv::Vec3b(200, 90, 40)},
      {cv::Vec3b(24, 22, 22), cv::Vec3b(130, 130, 132)}};
  for (const auto& [top, bottom] : cases) {
    Scene s = painted(top, 0.0);
    for (int y = 180; y < s.bgr.rows; ++y)
      for (int x = 0; x < s.bgr.cols; ++x)
        if (s.mask(y, x))
          s.bgr(y, x) = bottom;
    blur(s);
    const GarmentColours c = garmentColours(s.bgr, s.mask);
    EXPECT_EQ(c.colours.size(), 2u) << c.label();
  }
}

TEST(GarmentColours, RefusesBadInput) {
  EXPECT_THROW(garmentColours(cv::Mat3b(10, 10), cv::Mat1b::zeros(10, 11)), std::invalid_argument);
  EXPECT_THROW(garmentColours(cv::Mat3b(50, 50, cv::Vec3b(1, 2, 3)), cv::Mat1b::zeros(50, 50)),
               std::invalid_argument);
}

}  // namespace
}  // namespace garmcap::daemon
