#include "garmcap/pipeline/grabcut_refine.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

namespace {

// A green screen with a grey form and a striped garment whose outline is known exactly.
struct Scene {
  cv::Mat bgr;
  cv::Mat truth;   // garment mask
  cv::Mat trimap;  // green = sure background, eroded garment = sure foreground, rest probable
};

Scene makeScene(cv::Size size, unsigned seed) {
  Scene s;
  s.bgr = cv::Mat(size, CV_8UC3, cv::Scalar(60, 180, 70));
  const cv::Point centre(size.width / 2, size.height / 2);
  cv::ellipse(s.bgr, centre, cv::Size(size.width / 6, size.height / 2 - 10), 0, 0, 360,
              cv::Scalar(200, 205, 210), cv::FILLED);
  s.truth = cv::Mat::zeros(size, CV_8UC1);
  std::vector<cv::Point> dress = {{centre.x - size.width / 8, size.height / 5},
                                  {centre.x + size.width / 8, size.height / 5},
                                  {centre.x + size.width / 4, size.height * 4 / 5},
                                  {centre.x - size.width / 4, size.height * 4 / 5}};
  cv::fillConvexPoly(s.truth, dress, cv::Scalar(255), cv::LINE_8);
  cv::Mat stripes(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y)
    stripes.row(y).setTo((y / 12) % 2 ? cv::Scalar(40, 40, 160) : cv::Scalar(230, 230, 240));
  stripes.copyTo(s.bgr, s.truth);
  cv::Mat noise(size, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0, 6);
  s.bgr += noise;
  cv::GaussianBlur(s.bgr, s.bgr, cv::Size(3, 3), 0);

  cv::Mat hsv;
  cv::cvtColor(s.bgr, hsv, cv::COLOR_BGR2HSV);
  cv::Mat green;
  cv::inRange(hsv, cv::Scalar(40, 80, 60), cv::Scalar(85, 255, 255), green);
  s.trimap = cv::Mat(size, CV_8UC1, cv::Scalar(cv::GC_PR_BGD));
  cv::Mat sure;
  cv::erode(s.truth, sure, cv::Mat(), cv::Point(-1, -1), 15);
  s.trimap.setTo(cv::Scalar(cv::GC_PR_FGD), s.truth);  // a slightly wrong prior is fine
  s.trimap.setTo(cv::Scalar(cv::GC_FGD), sure);
  s.trimap.setTo(cv::Scalar(cv::GC_BGD), green);
  return s;
}

}  // namespace

TEST(GrabCutCoarseToFine, MatchesFullResolutionGrabCutAndTruth) {
  const Scene s = makeScene(cv::Size(1000, 750), 7);
  const cv::Mat fast = grabCutCoarseToFine(s.bgr, s.trimap, {.workMegapixels = 0.1});
  const cv::Mat full = grabCutFullResolution(s.bgr, s.trimap, 2);
  EXPECT_GT(maskIou(fast, full), 0.99);
  EXPECT_GT(maskIou(fast, s.truth), 0.98);
}

// The band cut must be the cut cv::grabCut makes on the whole frame with the same frozen models:
// same energy, same beta, same maxflow, only a smaller graph.
TEST(GrabCutFrozen, EqualsWholeFrameGrabCutWithFrozenModels) {
  for (const unsigned seed : {5u, 9u}) {
    const Scene s = makeScene(cv::Size(480, 360), seed);
    cv::Mat learned = s.trimap.clone();
    cv::Mat bgdModel, fgdModel;
    cv::theRNG().state = 1;
    cv::grabCut(s.bgr, learned, cv::Rect(), bgdModel, fgdModel, 1, cv::GC_INIT_WITH_MASK);
    // A band of open labels around the truth's outline, hard labels elsewhere.
    cv::Mat edge, band;
    cv::morphologyEx(s.truth, edge, cv::MORPH_GRADIENT, cv::Mat());
    cv::dilate(edge, band, cv::Mat(), cv::Point(-1, -1), 6);
    cv::Mat labels(s.truth.size(), CV_8UC1, cv::Scalar(cv::GC_BGD));
    labels.setTo(cv::GC_FGD, s.truth);
    labels.setTo(cv::GC_PR_FGD, band & s.truth);
    labels.setTo(cv::GC_PR_BGD, band & ~s.truth);
    const int open = cv::countNonZero(band);
    ASSERT_GT(open, 1000);

    cv::Mat reference = labels.clone();
    cv::Mat bgd = bgdModel.clone(), fgd = fgdModel.clone();
    cv::grabCut(s.bgr, reference, cv::Rect(), bgd, fgd, 1, cv::GC_EVAL_FREEZE_MODEL);
    const cv::Mat ours = grabCutFrozen(s.bgr, labels, bgdModel, fgdModel);
    EXPECT_EQ(cv::countNonZero((ours != labels) & ~band), 0) << "a hard label changed";
    const int differ = cv::countNonZero(ours != reference);
    EXPECT_LE(differ, open / 1000)
        << "seed " << seed << ": " << differ << " of " << open << " band pixels cut differently";
    // And the cut is not trivial: both labels occur in the band.
    EXPECT_GT(cv::countNonZero((ours == cv::GC_PR_FGD) & band), 0);
    EXPECT_GT(cv::countNonZero((ours == cv::GC_PR_BGD) & band), 0);
  }
}

TEST(GrabCutFrozen, RejectsMalformedModels) {
  const Scene s = makeScene(cv::Size(160, 120), 2);
  const cv::Mat model(1, 64, CV_64FC1, cv::Scalar(0));
  EXPECT_THROW(grabCutFrozen(s.bgr, s.trimap, model, model), std::invalid_argument);
}

TEST(GrabCutCoarseToFine, NeverChangesHardLabels) {
  const Scene s = makeScene(cv::Size(800, 600), 3);
  const cv::Mat fast = grabCutCoarseToFine(s.bgr, s.trimap, {.workMegapixels = 0.1});
  EXPECT_EQ(cv::countNonZero(fast & (s.trimap == cv::GC_BGD + 0)), 0);
  EXPECT_EQ(cv::countNonZero(~fast & (s.trimap == cv::GC_FGD + 0)), 0);
}

TEST(GrabCutCoarseToFine, RejectsInvalidLabelsAndShapes) {
  const Scene s = makeScene(cv::Size(320, 240), 1);
  cv::Mat bad = s.trimap.clone();
  bad.at<uchar>(0, 0) = 255;
  EXPECT_THROW(grabCutCoarseToFine(s.bgr, bad), std::invalid_argument);
  EXPECT_THROW(grabCutCoarseToFine(s.bgr, cv::Mat(10, 10, CV_8UC1, cv::Scalar(0))),
               std::invalid_argument);
}

TEST(GrabCutCoarseToFine, OneClassTrimapReturnsItsForeground) {
  const cv::Mat bgr(100, 100, CV_8UC3, cv::Scalar(0, 255, 0));
  const cv::Mat allBg(100, 100, CV_8UC1, cv::Scalar(cv::GC_BGD));
  EXPECT_EQ(cv::countNonZero(grabCutCoarseToFine(bgr, allBg)), 0);
}
