#include "garmcap/pipeline/garment_classifier.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

namespace {

const cv::Size kFrame(480, 640);

// Simple garment silhouettes on a form standing in the middle of the frame.
cv::Mat topMask(bool sleeves) {
  cv::Mat m = cv::Mat::zeros(kFrame, CV_8UC1);
  cv::rectangle(m, cv::Rect(190, 120, 100, 170), cv::Scalar(255), cv::FILLED);
  if (sleeves) {
    cv::line(m, {195, 130}, {140, 300}, cv::Scalar(255), 26);
    cv::line(m, {285, 130}, {340, 300}, cv::Scalar(255), 26);
  }
  return m;
}
cv::Mat skirtMask(bool aLine) {
  cv::Mat m = cv::Mat::zeros(kFrame, CV_8UC1);
  const int flare = aLine ? 45 : 8;
  std::vector<cv::Point> poly = {{200, 270}, {280, 270}, {285 + flare, 450}, {195 - flare, 450}};
  cv::fillConvexPoly(m, poly, cv::Scalar(255));
  return m;
}
cv::Mat pantsMask() {
  cv::Mat m = cv::Mat::zeros(kFrame, CV_8UC1);
  cv::rectangle(m, cv::Rect(195, 270, 90, 60), cv::Scalar(255), cv::FILLED);
  cv::rectangle(m, cv::Rect(195, 320, 38, 260), cv::Scalar(255), cv::FILLED);
  cv::rectangle(m, cv::Rect(247, 320, 38, 260), cv::Scalar(255), cv::FILLED);
  return m;
}
cv::Mat dressMask(bool aLine) {
  cv::Mat m = topMask(false) | skirtMask(aLine);
  cv::rectangle(m, cv::Rect(195, 260, 90, 20), cv::Scalar(255), cv::FILLED);
  return m;
}

std::vector<ReferenceSilhouette> database() {
  return {
      {"top", {{"sleeve", "none"}}, topMask(false)},
      {"top", {{"sleeve", "long"}}, topMask(true)},
      {"skirt", {{"skirt", "a_line"}}, skirtMask(true)},
      {"skirt", {{"skirt", "h_line"}}, skirtMask(false)},
      {"pants", {}, pantsMask()},
      {"dress", {{"sleeve", "none"}, {"skirt", "a_line"}}, dressMask(true)},
      {"dress", {{"sleeve", "none"}, {"skirt", "h_line"}}, dressMask(false)},
  };
}

// A query a little different from the references: shifted and slightly grown.
cv::Mat perturb(const cv::Mat& m) {
  cv::Mat out;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1.03, 0, -4, 0, 1.02, 3);
  cv::warpAffine(m, out, shift, m.size(), cv::INTER_NEAREST);
  return out;
}

}  // namespace

TEST(GarmentClassifier, EachMethodRecognisesPerturbedReferences) {
  const GarmentClassifier classifier(database());
  const std::vector<std::pair<cv::Mat, std::string>> cases = {{topMask(true), "top"},
                                                              {skirtMask(true), "skirt"},
                                                              {pantsMask(), "pants"},
                                                              {dressMask(false), "dress"}};
  for (MatchMethod method :
       {MatchMethod::kIou, MatchMethod::kChamfer, MatchMethod::kShapeContext}) {
    for (const auto& [mask, type] : cases) {
      const Classification c = classifier.classify(perturb(mask), method);
      EXPECT_EQ(c.type, type) << toString(method);
      EXPECT_GT(c.confidence, 0.5) << toString(method) << " " << type;
      EXPECT_NE(c.runnerUp, type);
    }
  }
}

TEST(GarmentClassifier, AttributesComeFromTheNearestReference) {
  const GarmentClassifier classifier(database());
  EXPECT_EQ(
      classifier.classify(perturb(skirtMask(false)), MatchMethod::kIou).attributes.at("skirt"),
      "h_line");
  EXPECT_EQ(classifier.classify(perturb(topMask(false)), MatchMethod::kIou).attributes.at("sleeve"),
            "none");
}

TEST(GarmentClassifier, UnmatchedShapeIsUnknownNotForced) {
  const GarmentClassifier classifier(database());
  cv::Mat blob = cv::Mat::zeros(kFrame, CV_8UC1);
  cv::circle(blob, {100, 100}, 60, cv::Scalar(255), cv::FILLED);
  for (MatchMethod method :
       {MatchMethod::kIou, MatchMethod::kChamfer, MatchMethod::kShapeContext}) {
    const Classification c = classifier.classify(blob, method);
    EXPECT_EQ(c.type, "unknown") << toString(method);
    EXPECT_EQ(c.confidence, 0);
  }
  EXPECT_EQ(classifier.classify(cv::Mat::zeros(kFrame, CV_8UC1), MatchMethod::kIou).type,
            "unknown");
}

TEST(GarmentClassifier, RefusesAnEmptyDatabase) {
  EXPECT_THROW(GarmentClassifier({}), std::invalid_argument);
}

TEST(ShapeContext, ResamplingIsIndependentOfContourStart) {
  std::vector<cv::Point> square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  std::vector<cv::Point> rotated = {{10, 10}, {0, 10}, {0, 0}, {10, 0}};
  const auto a = resampleContour(square, 8);
  const auto b = resampleContour(rotated, 8);
  ASSERT_EQ(a.size(), 8u);
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_LT(cv::norm(a[i] - b[i]), 1e-4);
}
