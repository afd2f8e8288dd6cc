#include "garmcap/pipeline/product_images.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

namespace {

const cv::Vec3b kScreen(40, 200, 40);
const cv::Vec3b kForm(150, 180, 205);  // beige

double meanA(const cv::Mat3b& bgr, const cv::Mat1b& where) {
  cv::Mat f, lab;
  bgr.convertTo(f, CV_32F, 1.0 / 255.0);
  cv::cvtColor(f, lab, cv::COLOR_BGR2Lab);
  std::vector<cv::Mat> ch;
  cv::split(lab, ch);
  return cv::mean(ch[1], where)[0];
}

}  // namespace

TEST(ProductImages, SquareAndPortraitCentredAtFullResolution) {
  cv::Mat3b frame(600, 800, kScreen);
  cv::Mat1f alpha = cv::Mat1f::zeros(frame.size());
  cv::rectangle(frame, cv::Rect(100, 50, 200, 400), cv::Scalar(30, 60, 200), cv::FILLED);
  cv::rectangle(alpha, cv::Rect(100, 50, 200, 400), cv::Scalar(1.0), cv::FILLED);

  const ProductImages p = makeProductImages(frame, alpha, {.maxSidePx = 4096});
  // 400 px of garment, 6 % margin a side: 455 px, never scaled down to a fixed size.
  EXPECT_EQ(p.square.rows, 455);
  EXPECT_EQ(p.square.cols, 455);
  EXPECT_EQ(p.portrait.rows, 455);
  EXPECT_EQ(p.portrait.cols, 364);
  EXPECT_EQ(p.garmentBox, cv::Rect(100, 50, 200, 400));
  for (const cv::Mat3b img : {p.square, p.portrait}) {
    EXPECT_EQ(img(0, 0), cv::Vec3b(255, 255, 255));
    const cv::Vec3b centre = img(img.rows / 2, img.cols / 2);
    EXPECT_EQ(centre, cv::Vec3b(30, 60, 200));
    cv::Mat1b grey;
    cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
    const cv::Rect box = cv::boundingRect(grey < 255);
    EXPECT_NEAR(box.x, img.cols - box.br().x, 1);
    EXPECT_NEAR(box.y, img.rows - box.br().y, 1);
  }
  ASSERT_EQ(p.cutout.type(), CV_8UC4);
  EXPECT_EQ(p.cutout.size(), p.cutoutRect.size());
  EXPECT_EQ(p.cutout.at<cv::Vec4b>(0, 0)[3], 0);
  // A cap on the side scales down, keeping the aspect.
  const ProductImages small = makeProductImages(frame, alpha, {.maxSidePx = 200});
  EXPECT_EQ(small.square.cols, 200);
  EXPECT_EQ(small.portrait.rows, 200);
  EXPECT_EQ(small.portrait.cols, 160);
  // A floor on the side scales up, by 1.5x at most.
  const ProductImages zoom = makeProductImages(frame, alpha, {.minSidePx = 600});
  EXPECT_EQ(zoom.square.cols, 600);
  EXPECT_EQ(zoom.portrait.rows, 600);
  EXPECT_EQ(makeProductImages(frame, alpha, {.minSidePx = 2048}).square.cols, 683);
  EXPECT_THROW(makeProductImages(frame, cv::Mat1f::zeros(frame.size())), std::invalid_argument);
  EXPECT_THROW(makeProductImages(frame, cv::Mat1f::zeros(10, 10)), std::invalid_argument);
}

// A garment over a form, its mask taking in a 4 px sliver of the form at its side and a rim at
// its top (as a work-frame cut upsampled does): both look as they did in the bare frame and run
// to the outside, so they are cut; the garment itself is kept whole.
TEST(ProductImages, FormRemainsAtTheOutlineAreCut) {
  cv::Mat3b bare(400, 300, kScreen);
  cv::rectangle(bare, cv::Rect(80, 20, 140, 360), cv::Scalar(kForm), cv::FILLED);
  cv::Mat3b dressed = bare.clone();
  const cv::Rect garment(80, 120, 100, 150);
  cv::rectangle(dressed, garment, cv::Scalar(90, 40, 40), cv::FILLED);
  cv::Mat1b mask = cv::Mat1b::zeros(bare.size());
  cv::rectangle(mask, cv::Rect(80, 114, 104, 156), cv::Scalar(255), cv::FILLED);

  const cv::Mat1b cut = formRemains(dressed, bare, mask, 10, 5.0);
  cv::Mat1b garmentMask = cv::Mat1b::zeros(bare.size());
  cv::rectangle(garmentMask, garment, cv::Scalar(255), cv::FILLED);
  cv::Mat1b inner;
  cv::erode(garmentMask, inner, cv::Mat(), cv::Point(-1, -1), 2);
  EXPECT_EQ(cv::countNonZero(cut & inner), 0) << "garment cut";
  cv::Mat1b remains = mask & ~garmentMask;
  cv::erode(remains, remains, cv::Mat(), cv::Point(-1, -1), 2);  // the blur's reach
  EXPECT_EQ(cv::countNonZero(remains & ~cut), 0) << "form left";

  // A print the colour of the form where the bare frame shows the form, enclosed by the garment:
  // it looks as the bare frame did but does not reach the outline, so it stays.
  cv::Mat3b printed = dressed.clone();
  const cv::Rect patch(110, 160, 20, 20);
  bare(patch).copyTo(printed(patch));
  EXPECT_EQ(cv::countNonZero(formRemains(printed, bare, mask, 40, 5.0)(patch)), 0);
  EXPECT_THROW(formRemains(dressed, bare, cv::Mat1b::zeros(10, 10), 5, 5), std::invalid_argument);
}

// A sliver of form beside a garment a shade darker than the form (88 % of it, 8.9 CIELAB units),
// tinted by the screen's spill in the dressed frame only (8 % of the screen's colour: 7.7 units
// off the bare frame, over the 5-unit threshold, and 11.6 from the garment): told by the
// screen's colour, the cut takes it for form; without it, it stays (seed 11's pants' crotch).
// A light patch in the garment near the form's colour but not tinted towards the screen stays.
TEST(ProductImages, SpillTintedFormBesideTheGarmentIsCut) {
  cv::Mat3b bare(400, 300, kScreen);
  cv::rectangle(bare, cv::Rect(80, 20, 140, 360), cv::Scalar(kForm), cv::FILLED);
  cv::Mat3b dressed = bare.clone();
  const cv::Rect garment(80, 120, 100, 150);
  cv::rectangle(dressed, garment, cv::Scalar(132, 158, 180), cv::FILLED);
  const cv::Rect sliver(180, 120, 4, 150);
  cv::Mat3f tinted;
  cv::Mat3b(sliver.size(), kForm).convertTo(tinted, CV_32F);
  tinted = tinted * 0.92 + cv::Mat3f(sliver.size(), cv::Vec3f(kScreen) * 0.08f);
  tinted.convertTo(dressed(sliver), CV_8U);
  cv::Mat1b mask = cv::Mat1b::zeros(bare.size());
  cv::rectangle(mask, cv::Rect(80, 120, 104, 150), cv::Scalar(255), cv::FILLED);
  cv::Mat1b inner = cv::Mat1b::zeros(bare.size());
  cv::rectangle(inner, cv::Rect(sliver.x + 1, sliver.y + 2, sliver.width - 1, sliver.height - 4),
                cv::Scalar(255), cv::FILLED);  // a pixel clear of the garment's blur
  EXPECT_GT(cv::countNonZero(inner & ~formRemains(dressed, bare, mask, 10, 5.0)), 0)
      << "the tint is over the threshold, so without the screen's colour it stays";
  const cv::Mat1b cut = formRemains(dressed, bare, mask, 10, 5.0, kScreen);
  EXPECT_EQ(cv::countNonZero(inner & ~cut), 0) << "spill-tinted form left";
  cv::Mat1b garmentInner = cv::Mat1b::zeros(bare.size());
  cv::rectangle(garmentInner, cv::Rect(82, 122, 96, 146), cv::Scalar(255), cv::FILLED);
  EXPECT_EQ(cv::countNonZero(cut & garmentInner), 0) << "garment cut";
  // A light patch at the garment's edge, 7.2 units off the form, lighter and bluer (not towards
  // the screen's green).
  cv::Mat3b patched = dressed.clone();
  const cv::Rect patch(160, 160, 20, 20);
  patched(patch).setTo(cv::Scalar(170, 190, 215));
  EXPECT_EQ(cv::countNonZero(formRemains(patched, bare, mask, 10, 5.0, kScreen)(
                cv::Rect(patch.x, patch.y + 2, patch.width - 2, patch.height - 4))),
            0)
      << "a light patch untinted by the screen is garment";
}

// Spill as a screen tints an edge: the pixel mixed with the screen's colour, fading inwards.
// After the despill the edge's a* is within 2 units of the inside's; a red garment edge (no
// spill) keeps its chroma.
TEST(ProductImages, DespillBringsTheEdgeToTheInsideChroma) {
  const cv::Vec3f skin(150, 175, 230);
  cv::Mat3b img(300, 300, kScreen);
  cv::Mat1f alpha = cv::Mat1f::zeros(img.size());
  const cv::Rect g(50, 50, 200, 200);
  cv::rectangle(alpha, g, cv::Scalar(1.0), cv::FILLED);
  for (int y = g.y; y < g.br().y; ++y)
    for (int x = g.x; x < g.br().x; ++x) {
      const int d = std::min({x - g.x, g.br().x - 1 - x, y - g.y, g.br().y - 1 - y});
      const float w = 0.3f * std::exp(-d / 8.0f);
      const cv::Vec3f c = skin * (1 - w) + cv::Vec3f(kScreen[0], kScreen[1], kScreen[2]) * w;
      img(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                            cv::saturate_cast<uchar>(c[2]));
    }
  cv::Mat1b edge = cv::Mat1b::zeros(img.size()), inside = cv::Mat1b::zeros(img.size());
  cv::rectangle(edge, g, cv::Scalar(255), cv::FILLED);
  cv::rectangle(edge, cv::Rect(g.x + 3, g.y + 3, g.width - 6, g.height - 6), cv::Scalar(0),
                cv::FILLED);
  cv::rectangle(inside, cv::Rect(g.x + 60, g.y + 60, g.width - 120, g.height - 120),
                cv::Scalar(255), cv::FILLED);
  const double before = meanA(img, edge) - meanA(img, inside);
  EXPECT_LT(before, -5.0) << "the test's spill is too weak to show anything";
  despillEdge(img, alpha, kScreen, 40);
  EXPECT_NEAR(meanA(img, edge), meanA(img, inside), 2.0) << "before: " << before;

  cv::Mat3b red(300, 300, kScreen);
  cv::rectangle(red, g, cv::Scalar(40, 40, 200), cv::FILLED);
  const cv::Mat3b redBefore = red.clone();
  despillEdge(red, alpha, kScreen, 40);
  EXPECT_NEAR(meanA(red, edge), meanA(redBefore, edge), 0.5);
}

TEST(ProductImages, RefinedAlphaFollowsTheFramesEdge) {
  // The frame's edge at x = 100; the mask's a few px off (a work-frame cut upsampled).
  cv::Mat3b img(100, 200, kScreen);
  cv::rectangle(img, cv::Rect(0, 0, 100, 100), cv::Scalar(200, 200, 200), cv::FILLED);
  cv::Mat1b mask = cv::Mat1b::zeros(img.size());
  cv::rectangle(mask, cv::Rect(0, 0, 102, 100), cv::Scalar(255), cv::FILLED);
  const cv::Mat1f a = refinedAlpha(img, mask, 4);
  EXPECT_GT(a(50, 97), 0.9f);
  EXPECT_LT(a(50, 101), 0.5f);
  EXPECT_EQ(a(50, 20), 1.0f);
  EXPECT_EQ(a(50, 180), 0.0f);
}

namespace {

// A garment of `size` with a print (noise, so that any change to its pixels shows) and a soft
// alpha edge, on the screen of a 600x800 frame; the composite a plain white background gives
// (written out here, apart from onWhite) placed as the photos centre it.
struct ShadowScene {
  cv::Mat3b frame;
  cv::Mat1f alpha;
  cv::Rect box;
};

ShadowScene shadowScene(cv::Size size) {
  ShadowScene s{cv::Mat3b(600, 800, kScreen), cv::Mat1f::zeros(600, 800), {}};
  const cv::Rect garment(cv::Point(400 - size.width / 2, 300 - size.height / 2), size);
  cv::Mat3b print(size);
  cv::theRNG().state = 17;
  cv::randu(print, cv::Scalar(20, 40, 60), cv::Scalar(120, 140, 220));
  print.copyTo(s.frame(garment));
  cv::rectangle(s.alpha, garment, cv::Scalar(1.0), cv::FILLED);
  cv::GaussianBlur(s.alpha, s.alpha, cv::Size(5, 5), 1.2);
  s.alpha.setTo(0.0f, s.alpha < 1e-3f);
  s.box = cv::boundingRect(s.alpha > 0.0f);
  return s;
}

cv::Mat3b plainOnWhite(const ShadowScene& s, cv::Size canvas) {
  cv::Mat3b out(canvas, cv::Vec3b(255, 255, 255));
  const cv::Point at((canvas.width - s.box.width) / 2, (canvas.height - s.box.height) / 2);
  for (int y = 0; y < s.box.height; ++y)
    for (int x = 0; x < s.box.width; ++x) {
      const float a = s.alpha(s.box.y + y, s.box.x + x);
      if (a > 0.f)
        for (int c = 0; c < 3; ++c)
          out(at.y + y, at.x + x)[c] = cv::saturate_cast<uchar>(
              s.frame(s.box.y + y, s.box.x + x)[c] * a + 255.f * (1.f - a));
    }
  return out;
}

}  // namespace

// Off (the default), the photos are the garment on pure white, exactly as before the option.
TEST(ProductImages, WithoutShadowTheBackgroundIsPureWhite) {
  const ShadowScene s = shadowScene({200, 400});
  const ProductImages p = makeProductImages(s.frame, s.alpha, {});
  for (const cv::Mat3b img : {p.square, p.portrait}) {
    const cv::Mat3b expected = plainOnWhite(s, img.size());
    EXPECT_EQ(cv::norm(img, expected, cv::NORM_INF), 0.0);
  }
}

// On: the band just under the hem is darker than white, fading smoothly to pure white within the
// bottom margin; the garment's fully covered pixels are as without the shadow; the margins to
// the left, right and top are pure white. For a tall, a wide and a square garment (the square one
// leaves the least margin in the square photo).
TEST(ProductImages, SoftShadowFallsUnderTheGarmentOnly) {
  for (const cv::Size size : {cv::Size(200, 400), cv::Size(460, 300), cv::Size(360, 360)}) {
    SCOPED_TRACE(testing::Message() << size);
    const ShadowScene s = shadowScene(size);
    const ProductImages off = makeProductImages(s.frame, s.alpha, {});
    const ProductImages on = makeProductImages(s.frame, s.alpha, {.shadow = true});
    for (int which = 0; which < 2; ++which) {
      SCOPED_TRACE(which == 0 ? "square" : "4:5");
      const cv::Mat3b a = which == 0 ? off.square : off.portrait;
      const cv::Mat3b b = which == 0 ? on.square : on.portrait;
      ASSERT_EQ(a.size(), b.size());
      const cv::Point at((b.cols - s.box.width) / 2, (b.rows - s.box.height) / 2);
      // The garment's own pixels (fully covered) are untouched.
      cv::Mat1b covered = cv::Mat1b::zeros(b.size());
      cv::Mat1b(s.alpha(s.box) >= 1.0f).copyTo(covered(cv::Rect(at, s.box.size())));
      ASSERT_GT(cv::countNonZero(covered), size.area() / 2);
      cv::Mat3b diff;
      cv::absdiff(a, b, diff);
      cv::Mat1b differs;  // the largest difference of the three channels, per pixel
      cv::reduce(diff.reshape(1, a.rows * a.cols), differs, 1, cv::REDUCE_MAX);
      EXPECT_EQ(cv::countNonZero(differs.reshape(1, a.rows) & covered), 0);

      cv::Mat1b grey;
      cv::cvtColor(b, grey, cv::COLOR_BGR2GRAY);
      // The band just under the lowest row any garment covers, across the garment's middle half.
      const int hem = at.y + s.box.height;  // first row below the garment
      const cv::Rect middle(at.x + s.box.width / 4, 0, s.box.width / 2, b.rows);
      const int bandRows = std::max(2, size.height / 100);
      const double band = cv::mean(grey(cv::Rect(middle.x, hem, middle.width, bandRows)))[0];
      EXPECT_LT(band, 255.0 - 25.0) << "no shadow to see under the hem";
      EXPECT_GT(band, 255.0 - 70.0) << "a dark band, not a soft shadow";
      // Falling off smoothly: each row down the middle column is as light or lighter, with no
      // step of more than a few grey levels, and pure white before the photo's edge.
      const int mid = at.x + s.box.width / 2;
      for (int y = hem + 1; y < b.rows; ++y) {
        EXPECT_GE(grey(y, mid), grey(y - 1, mid)) << "row " << y;
        EXPECT_LE(grey(y, mid) - grey(y - 1, mid), 6) << "row " << y;
      }
      EXPECT_EQ(cv::countNonZero(grey.row(b.rows - 1) != 255), 0) << "shadow cut at the edge";
      // The margins (6 % of the photo's width to the left and right, of its height at the top):
      // pure white.
      const int mx = static_cast<int>(0.06 * b.cols), my = static_cast<int>(0.06 * b.rows);
      for (const cv::Rect r : {cv::Rect(0, 0, mx, b.rows), cv::Rect(b.cols - mx, 0, mx, b.rows),
                               cv::Rect(0, 0, b.cols, my)})
        EXPECT_EQ(cv::countNonZero(grey(r) != 255), 0) << r;
    }
  }
}

TEST(ProductImages, DropShadowIsEmptyWithoutAGarment) {
  EXPECT_EQ(cv::countNonZero(dropShadow(cv::Mat1f::zeros(50, 40))), 0);
}
