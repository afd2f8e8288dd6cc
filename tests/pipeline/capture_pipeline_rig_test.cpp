// GarmCap on the committed simulator rig (tests/data/rig): accuracy against truth.json and the
// refusals of bad input. Label "rig".
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/rig.h"
#include "garmcap/pipeline/capture_pipeline.h"

using namespace garmcap;
namespace fs = std::filesystem;

namespace {

const fs::path kRig = fs::path(GARMCAP_TEST_DATA_DIR) / "rig";

pipeline::CaptureOptions fastOptions() {
  pipeline::CaptureOptions o;
  o.makeProductImages = false;
  o.makeTexture = false;
  return o;
}

capture::RigCase firstCase() {
  const auto rig = capture::readRig(kRig);
  return capture::loadRigCase(rig.cases.front().dir);
}

pipeline::CaptureError::Reason reasonOf(const cv::Mat& e, const cv::Mat& d,
                                        const nlohmann::json& cal) {
  try {
    pipeline::runCapture(e, d, cal, fastOptions());
  } catch (const pipeline::CaptureError& err) {
    return err.reason();
  }
  ADD_FAILURE() << "expected a CaptureError";
  return pipeline::CaptureError::Reason::kBadInput;
}

}  // namespace

TEST(CapturePipelineRig, MeetsAccuracyOnTheBundledRig) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto rig = capture::readRig(kRig);
  int typeOk = 0, attrOk = 0, attrN = 0;
  std::map<std::string, std::pair<double, double>> err;  // name -> (sum abs, max abs)
  std::map<std::string, int> count;
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    const auto r = pipeline::runCapture(c.empty, c.dressed, c.calibration, fastOptions());
    const std::string truthType = c.truth.at("type");
    EXPECT_EQ(r.type, truthType) << c.id;
    typeOk += r.type == truthType;
    for (const auto& [k, v] : c.truth.at("attributes").items()) {
      ++attrN;
      const auto it = r.attributes.find(k);
      attrOk += it != r.attributes.end() && it->second == v.get<std::string>();
    }
    for (const auto& [k, v] : c.truth.at("measurements").items()) {
      const auto it = r.measurements.find(k);
      ASSERT_NE(it, r.measurements.end()) << c.id << " lacks " << k;
      const double e = std::abs(it->second - v.get<double>());
      err[k].first += e;
      err[k].second = std::max(err[k].second, e);
      ++count[k];
      EXPECT_LE(e, 1.5) << c.id << " " << k << " measured " << it->second << " truth " << v;
    }
  }
  EXPECT_EQ(typeOk, static_cast<int>(rig.cases.size()));
  EXPECT_GE(attrOk, 0.95 * attrN);
  for (const auto& [k, e] : err)
    EXPECT_LE(e.first / count[k], 0.7) << k;
}

TEST(CapturePipelineRig, IdenticalFramesHaveNoGarment) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  EXPECT_EQ(reasonOf(c.empty, c.empty.clone(), c.calibration),
            pipeline::CaptureError::Reason::kNoGarment);
}

TEST(CapturePipelineRig, MovedCameraIsRefused) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  cv::Mat moved;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 0, 0, 1, 40);
  cv::warpAffine(c.dressed, moved, shift, c.dressed.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  EXPECT_EQ(reasonOf(c.empty, moved, c.calibration), pipeline::CaptureError::Reason::kCameraMoved);
}

TEST(CapturePipelineRig, WrongFrameSizeIsRefused) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  cv::Mat small;
  cv::resize(c.dressed, small, cv::Size(), 0.5, 0.5);
  EXPECT_EQ(reasonOf(c.empty, small, c.calibration), pipeline::CaptureError::Reason::kBadInput);
  EXPECT_EQ(reasonOf(c.empty, cv::Mat(), c.calibration), pipeline::CaptureError::Reason::kBadInput);
}

TEST(CapturePipelineRig, GarmentOffTheFormIsRefused) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  // A red cloth hanging in front of the screen beside the form, not on it.
  cv::Mat dressed = c.empty.clone();
  const cv::Rect cloth(dressed.cols / 20, dressed.rows / 3, dressed.cols / 6, dressed.rows / 3);
  dressed(cloth).setTo(cv::Scalar(30, 30, 200));
  const auto reason = reasonOf(c.empty, dressed, c.calibration);
  EXPECT_TRUE(reason == pipeline::CaptureError::Reason::kOffForm) << static_cast<int>(reason);
}

TEST(CapturePipelineRig, MalformedCalibrationIsBadInput) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  nlohmann::json cal = c.calibration;
  cal.erase("pose");
  EXPECT_EQ(reasonOf(c.empty, c.dressed, cal), pipeline::CaptureError::Reason::kBadInput);
}
