// The ghost-mannequin composite (ghost_mannequin.h) on synthetic layers whose answer is known by
// construction: a garment mask with a drawn neck opening, a back layer of a distinct colour.
#include "garmcap/pipeline/ghost_mannequin.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "garmcap/pipeline/product_images.h"

using namespace garmcap::pipeline;

namespace {

// 200x220 frame, the form's axis at column 100. Body rows 60-199, columns 40-159; shoulders rows
// 30-59 at columns 40-79 and 120-159; so the neck opening is exactly rows 31-59 (just below the
// lid on row 30) by columns 80-119 plus the scoop `scoop` drawn below it.
constexpr int kW = 200, kH = 220;
constexpr double kAxis = 100.0;

cv::Mat1b garmentMask(const cv::Rect& scoop) {
  cv::Mat1b m = cv::Mat1b::zeros(kH, kW);
  m(cv::Rect(40, 60, 120, 140)).setTo(255);
  m(cv::Rect(40, 30, 40, 30)).setTo(255);
  m(cv::Rect(120, 30, 40, 30)).setTo(255);
  m(scoop).setTo(0);
  return m;
}

const cv::Rect kScoop(80, 60, 40, 25);  // the neckline dips to row 84

cv::Mat1b truthOpening() {
  cv::Mat1b t = cv::Mat1b::zeros(kH, kW);
  t(cv::Rect(80, 31, 40, 29)).setTo(255);
  t(kScoop).setTo(255);
  return t;
}

}  // namespace

TEST(NeckOpening, IsTheAreaTheOutlineEnclosesBelowTheLid) {
  const NeckOpening o = neckOpening(garmentMask(kScoop), kAxis);
  ASSERT_FALSE(o.region.empty()) << o.whyNone;
  EXPECT_EQ(cv::countNonZero(o.region != truthOpening()), 0);
  EXPECT_EQ(cv::countNonZero(o.region), 40 * 29 + 40 * 25);
}

TEST(NeckOpening, ASlopedLidFollowsTheNeckPoints) {
  // The right shoulder 10 rows lower: the lid runs from (79, 30) to (120, 40); above it nothing.
  cv::Mat1b m = garmentMask(kScoop);
  m(cv::Rect(120, 30, 40, 10)).setTo(0);
  const NeckOpening o = neckOpening(m, kAxis);
  ASSERT_FALSE(o.region.empty()) << o.whyNone;
  for (int x = 80; x < 120; ++x) {
    const double lid = 30.0 + 10.0 * (x - 79) / 41.0;
    for (int y = 0; y < kH; ++y) {
      const bool inside = y > lid && (y < 60 || (y < 85 && x >= 80 && x < 120));
      ASSERT_EQ(o.region(y, x) != 0, inside) << "at " << x << "," << y;
    }
  }
  EXPECT_EQ(cv::countNonZero(o.region(cv::Rect(0, 0, 80, kH))), 0);
  EXPECT_EQ(cv::countNonZero(o.region(cv::Rect(120, 0, 80, kH))), 0);
}

TEST(NeckOpening, NoneForAnOpenFrontOrOneSide) {
  // A slit from the neckline to the hem: not enclosed.
  cv::Mat1b open = garmentMask(kScoop);
  open(cv::Rect(98, 60, 4, 140)).setTo(0);
  const NeckOpening a = neckOpening(open, kAxis);
  EXPECT_TRUE(a.region.empty());
  EXPECT_NE(a.whyNone.find("open front"), std::string::npos) << a.whyNone;
  // Only the left half of a garment.
  cv::Mat1b half = garmentMask(kScoop);
  half(cv::Rect(100, 0, 100, kH)).setTo(0);
  const NeckOpening b = neckOpening(half, kAxis);
  EXPECT_TRUE(b.region.empty());
  EXPECT_FALSE(b.whyNone.empty());
}

TEST(MirroredLayer, MapsColumnsAboutTheAxis) {
  // A back layer covering frame rectangle (30, 20, 140, 190), left half blue, right half green.
  const cv::Rect from(30, 20, 140, 190);
  ProductLayer back{cv::Mat3b(from.size(), cv::Vec3b(200, 0, 0)), cv::Mat1f(from.size(), 1.0f)};
  back.colour(cv::Rect(70, 0, 70, from.height)).setTo(cv::Vec3b(0, 200, 0));  // frame x >= 100
  const cv::Rect to(35, 25, 130, 195);                                        // frame rows 25-219
  const ProductLayer m = mirroredLayer(back, from, kAxis, to);
  ASSERT_EQ(m.colour.size(), to.size());
  // Frame column x shows the back's column 200 - x: x < 100 shows the right (green) half.
  EXPECT_EQ(m.colour(50, 90 - to.x), cv::Vec3b(0, 200, 0));
  EXPECT_EQ(m.colour(50, 110 - to.x), cv::Vec3b(200, 0, 0));
  EXPECT_FLOAT_EQ(m.alpha(50, 90 - to.x), 1.0f);
  // Frame column 162 mirrors to 38, inside the layer; column 40 to 160, inside too; row 212 of
  // the frame is below the layer (rows 20-209): alpha 0.
  ASSERT_LT(212 - to.y, m.alpha.rows);
  EXPECT_FLOAT_EQ(m.alpha(212 - to.y, 60 - to.x), 0.0f);
  EXPECT_FLOAT_EQ(m.alpha(205 - to.y, 60 - to.x), 1.0f);
}

TEST(ComposeGhostFront, FillsTheOpeningWithTheDarkenedBackAndNothingElse) {
  const cv::Mat1b mask = garmentMask(kScoop);
  // The front: red garment, the form's beige where it shows (alpha 0 there), and a soft rim of
  // alpha 0.5 one pixel wide round the neckline (inside the garment).
  ProductLayer front{cv::Mat3b(kH, kW, cv::Vec3b(150, 190, 210)), cv::Mat1f::zeros(kH, kW)};
  front.colour.setTo(cv::Vec3b(30, 30, 200), mask);
  front.alpha.setTo(1.0f, mask);
  const cv::Mat1b opening = truthOpening();
  cv::Mat1b rimBand;
  cv::dilate(opening, rimBand, cv::Mat());
  rimBand &= mask;
  front.alpha.setTo(0.5f, rimBand);
  // The inside: blue, alpha 1 everywhere but above row 40 (the back's neckline).
  ProductLayer inside{cv::Mat3b(kH, kW, cv::Vec3b(200, 60, 20)), cv::Mat1f(kH, kW, 1.0f)};
  inside.alpha(cv::Rect(0, 0, kW, 41)).setTo(0.0f);
  const ProductLayer before{front.colour.clone(), front.alpha.clone()};

  ProductLayer ghost{front.colour.clone(), front.alpha.clone()};
  const int changed = composeGhostFront(ghost, inside, opening, 2);
  const cv::Vec3b shaded(static_cast<uchar>(std::lround(0.8 * 200)),
                         static_cast<uchar>(std::lround(0.8 * 60)),
                         static_cast<uchar>(std::lround(0.8 * 20)));
  int filled = 0, rim = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (opening(y, x) && y > 40) {  // the back is there: its colour, darkened, opaque
        ASSERT_EQ(ghost.colour(y, x), shaded) << x << "," << y;
        ASSERT_FLOAT_EQ(ghost.alpha(y, x), 1.0f);
        ++filled;
      } else if (opening(y, x)) {  // above the back's neckline: still transparent, no form
        ASSERT_FLOAT_EQ(ghost.alpha(y, x), 0.0f);
      } else if (rimBand(y, x) && y > 40) {  // the soft neckline over the inside
        ASSERT_FLOAT_EQ(ghost.alpha(y, x), 1.0f);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(ghost.colour(y, x)[c], 0.5 * before.colour(y, x)[c] + 0.5 * shaded[c], 1.0);
        ++rim;
      } else {  // everything else keeps its bytes
        ASSERT_EQ(ghost.colour(y, x), before.colour(y, x)) << x << "," << y;
        ASSERT_EQ(ghost.alpha(y, x), before.alpha(y, x)) << x << "," << y;
      }
    }
  EXPECT_EQ(filled, 40 * 19 + 40 * 25);
  EXPECT_EQ(changed, filled + rim);

  // In the photos (no scaling, the box unchanged): every pixel outside the opening and its rim,
  // mapped onto the square canvas, is byte-identical to the photo without the ghost.
  const ProductImageOptions po{
      .maxSidePx = 4096, .minSidePx = 0, .marginFraction = 0.06, .pxPerCm = 10, .shadow = false};
  const ProductImages plain = makeProductImages(before.colour, before.alpha, po);
  const ProductImages withGhost = makeProductImages(ghost.colour, ghost.alpha, po);
  ASSERT_EQ(plain.garmentBox, withGhost.garmentBox);
  ASSERT_EQ(plain.square.size(), withGhost.square.size());
  const cv::Rect box = plain.garmentBox;
  const cv::Point offset((plain.square.cols - box.width) / 2, (plain.square.rows - box.height) / 2);
  cv::Mat1b touched = opening | rimBand;
  cv::Mat1b canvasTouched = cv::Mat1b::zeros(plain.square.size());
  touched(box).copyTo(canvasTouched(cv::Rect(offset, box.size())));
  const cv::Mat1b differs = [&] {
    cv::Mat diff;
    cv::absdiff(plain.square, withGhost.square, diff);
    cv::Mat1b d;
    cv::cvtColor(diff, d, cv::COLOR_BGR2GRAY);
    return cv::Mat1b(d > 0);
  }();
  EXPECT_EQ(cv::countNonZero(differs & ~canvasTouched), 0);
  // And inside the filled opening the photo shows the shaded back exactly.
  EXPECT_EQ(withGhost.square.at<cv::Vec3b>(offset.y + 70 - box.y, offset.x + 100 - box.x), shaded);
}
