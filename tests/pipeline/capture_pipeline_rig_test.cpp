// GarmCap on the committed simulator rig (tests/data/rig): accuracy against truth.json and the
// refusals of bad input. Label "rig".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/rig.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/pipeline/capture_context.h"
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

// A regression guard at the accuracy reached so far on the bundled rig (6 cases, 864x1152 JPEG,
// seed 2026), looser than the targets (type 100 %, mean error <= 0.7 cm, max <= 1.5 cm at
// 4 MP) by a margin for this rig's 1 MP. History: when the rig was made, 5 of 6 types, mean
// 0.49 cm, largest 2.8 cm; with the noise-floor exposed test 0.28 cm, largest 1.08 cm, the miss
// being case_001 (a dark green printed dress that keys as screen) reported as "unknown". With the
// bare-frame comparison for screen-coloured garments all 6 are typed: mean 0.27 cm over 33
// measurements, largest 0.84 cm (case_001's bust, read below its drooping sleeves). With the
// garments hanging (the rig's dressed frames re-rendered) and the measurer's hanging-depth
// section model, a different model from the simulator's (docs/measurement_model.md, "Section
// depth"): mean 0.32 cm, largest 1.00 cm; the bounds are unchanged.
TEST(CapturePipelineRig, RegressionGuardOnTheBundledRig) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto rig = capture::readRig(kRig);
  int typeOk = 0;
  double sumAbs = 0, maxAbs = 0;
  int n = 0, sleeved = 0;
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    const auto r = pipeline::runCapture(c.empty, c.dressed, c.calibration, fastOptions());
    const std::string truthType = c.truth.at("type");
    typeOk += r.type == truthType;
    if (r.type != truthType) {
      // A miss is owned up to, never a wrong type.
      EXPECT_EQ(r.type, "unknown") << c.id << " is a " << truthType;
      EXPECT_TRUE(info.hard) << c.id << ": only a hard case is expected to be missed";
      continue;
    }
    // A top or dress with sleeves gets its pattern, sleeve included, whatever the sleeve's
    // length: case_001's 10.6 cm dress sleeve, shorter than its cap, used to get none ("sleeve
    // shorter than its cap"); it is now drafted as a cap sleeve.
    const auto& tm = c.truth.at("measurements");
    if (tm.contains("sleeve_length") && tm.at("sleeve_length").get<double>() > 0) {
      bool sleeve = false;
      for (const auto& p : r.pattern.panels)
        sleeve = sleeve || p.name == "sleeve";
      std::string warnings;
      for (const auto& w : r.warnings)
        warnings += w + "; ";
      EXPECT_TRUE(sleeve) << c.id << " (" << truthType << ", sleeve " << tm.at("sleeve_length")
                          << " cm) has no sleeve pattern; warnings: " << warnings;
      ++sleeved;
    }
    for (const auto& [k, v] : c.truth.at("measurements").items()) {
      const auto it = r.measurements.find(k);
      // A reading the pipeline leaves out is a failure: dropping a hard reading must never
      // pass where a poor one would fail.
      if (it == r.measurements.end()) {
        ADD_FAILURE() << c.id << " " << k << " is missing";
        continue;
      }
      const double e = std::abs(it->second - v.get<double>());
      EXPECT_LE(e, 2.0) << c.id << " " << k << " measured " << it->second << " truth " << v;
      sumAbs += e;
      maxAbs = std::max(maxAbs, e);
      ++n;
    }
  }
  std::printf("bundled rig: %d of %zu types, mean |error| %.2f cm over %d measurements, max %.2f\n",
              typeOk, rig.cases.size(), n ? sumAbs / n : 0.0, n, maxAbs);
  EXPECT_EQ(typeOk, static_cast<int>(rig.cases.size()));
  EXPECT_GE(sleeved, 2);  // case_000's 21 cm top sleeve and case_001's 10.6 cm dress sleeve
  ASSERT_GT(n, 30);
  EXPECT_LE(sumAbs / n, 0.5);
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

// The prepared capture its caller owns gives what a capture on its own gives, as often as it is
// used, and refuses a capture that asks for another work frame than it was prepared for.
TEST(CapturePipelineRig, PreparedCaptureGivesTheOneOffResultEveryTime) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  const auto oneOff = pipeline::runCapture(c.empty, c.dressed, c.calibration, fastOptions());
  const pipeline::PreparedCapture prepared(
      pipeline::buildCaptureContext(c.calibration, pipeline::kDefaultSizeChart), c.empty,
      fastOptions().workMegapixels);
  for (int i = 0; i < 2; ++i) {
    const auto r = pipeline::runCapture(prepared, c.dressed, fastOptions());
    EXPECT_EQ(r.type, oneOff.type);
    EXPECT_EQ(r.measurements, oneOff.measurements);
    EXPECT_EQ(r.warnings, oneOff.warnings);
    EXPECT_EQ(cv::countNonZero(r.silhouette != oneOff.silhouette), 0);
  }
  pipeline::CaptureOptions other = fastOptions();
  other.workMegapixels = 0.5;
  try {
    pipeline::runCapture(prepared, c.dressed, other);
    ADD_FAILURE() << "expected a CaptureError";
  } catch (const pipeline::CaptureError& e) {
    EXPECT_EQ(e.reason(), pipeline::CaptureError::Reason::kBadInput);
    EXPECT_NE(std::string(e.what()).find("prepared for a 2.0 MP work frame"), std::string::npos)
        << e.what();
  }
}

// The form's body is completed from the chart the context is built with: names the form does not
// give come from one of that chart's sizes; an unknown chart is refused by name.
TEST(CapturePipelineRig, ContextBodyComesFromTheNamedChart) {
  if (!fs::exists(kRig / "rig.json"))
    GTEST_SKIP() << "no rig at " << kRig;
  const auto c = firstCase();
  int fromChart = 0;
  for (const char* name : {"korean_women", "italian_women"}) {
    const auto ctx = pipeline::buildCaptureContext(c.calibration, name);
    EXPECT_EQ(ctx->sizeChart, name);
    const auto& chart = drafts::sizeChart(name);
    for (const auto& [m, value] : ctx->body.values()) {
      if (ctx->form->measurements().find(m))
        continue;  // the form's own
      const bool inChart =
          std::any_of(chart.bodies.begin(), chart.bodies.end(),
                      [&](const auto& b) { return b.find(m) && *b.find(m) == value; });
      EXPECT_TRUE(inChart) << name << ": " << m << " = " << value;
      ++fromChart;
    }
  }
  EXPECT_GT(fromChart, 0);
  EXPECT_THROW(pipeline::buildCaptureContext(c.calibration, "no_such_chart"),
               std::invalid_argument);
}
