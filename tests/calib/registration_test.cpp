#include "garmcap/calib/registration.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "garmcap/calib/errors.h"
#include "synthetic_scene.h"
#include "test_forms.h"

namespace garmcap::calib {
namespace {

namespace fs = std::filesystem;

// Landmark tolerance: 2 px at 4 MP (2448 x 1632 rows), proportionally less at lower resolution
// because every error of the fit scales with the image.
double landmarkTolerancePx(cv::Size size) {
  return 2.0 * size.height / 1632.0;
}

struct Case {
  const char* name;
  cv::Size size;
  double fill;  // form height / image height
  double rollRad;
  bool perspective;
  bool grey;
};

void checkCase(const FormModel& form, const Case& c) {
  FormPose truth;
  truth.pxPerCm = c.fill * c.size.height / form.heightCm();
  truth.offsetPx = {0.53 * c.size.width, c.size.height * (0.5 + c.fill / 2) + 0.37};
  truth.rollRad = c.rollRad;
  RegistrationOptions options;
  if (c.perspective) {
    const double f = 1.1 * c.size.width;
    truth.perspective = Intrinsics{f, f, c.size.width / 2.0 + 7, c.size.height / 2.0 - 5};
    options.intrinsics = truth.perspective;
    options.distanceCm = *truth.distanceCm() * 1.08;  // a tape-measured distance, 8% off
  }
  test::SceneStyle style;
  if (c.grey)
    style.formBgr = {140, 140, 140};
  const cv::Mat3b scene = test::makeScene(form.mesh(), truth, c.size, style);
  const Registration reg = registerForm(form, scene, c.name, options);
  EXPECT_NEAR(reg.pose.pxPerCm / truth.pxPerCm, 1.0, 0.003) << c.name;
  EXPECT_GT(reg.iou, 0.98) << c.name;
  const auto expected = landmarkPoints(form, truth);
  ASSERT_EQ(expected.size(), reg.landmarks.size());
  double worst = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(expected[i].first, reg.landmarks[i].first);
    const double err = (expected[i].second - reg.landmarks[i].second).norm();
    worst = std::max(worst, err);
    EXPECT_LT(err, landmarkTolerancePx(c.size)) << c.name << " " << expected[i].first;
  }
  ::testing::Test::RecordProperty(std::string(c.name) + "_worst_landmark_px",
                                  std::to_string(worst));
  ::testing::Test::RecordProperty(std::string(c.name) + "_px_per_cm_error",
                                  std::to_string(reg.pose.pxPerCm / truth.pxPerCm - 1));
}

TEST(Registration, ParametricFormOrthographicSkinAndGrey) {
  checkCase(test::parametricForm55(), {"skin", {816, 544}, 0.85, 0.02, false, false});
  checkCase(test::parametricForm55(), {"grey", {816, 544}, 0.8, -0.03, false, true});
}

TEST(Registration, ParametricFormPerspective) {
  checkCase(test::parametricForm55(), {"perspective", {816, 544}, 0.85, 0.01, true, false});
}

TEST(Registration, RealMesh) {
  checkCase(test::realForm(), {"real", {816, 544}, 0.85, -0.015, false, false});
}

TEST(Registration, FourMegapixels) {
  checkCase(test::parametricForm55(), {"4mp", {2448, 1632}, 0.85, 0.012, false, false});
}

// A station frames the garment: the form's legs leave the frame at the bottom. The scene is drawn
// whole and cut at a form height, so the pose (origin at the top left) is the same; the fit must
// find it from what is in view.
double registerCut(const FormModel& form, double cutCm, bool perspective, const char* name,
                   double rollRad = 0.012) {
  const cv::Size whole(1000, 900);
  FormPose truth;
  truth.pxPerCm = 0.9 * whole.height / form.heightCm();
  truth.offsetPx = {0.51 * whole.width, 0.95 * whole.height + 0.3};
  truth.rollRad = rollRad;
  RegistrationOptions options;
  if (perspective) {
    const double f = 2.2 * whole.width;
    truth.perspective = Intrinsics{f, f, whole.width / 2.0 + 4, whole.height / 2.0 - 6};
    options.intrinsics = truth.perspective;
    options.distanceCm = *truth.distanceCm() * 1.05;
  }
  const cv::Mat3b scene = test::makeScene(form.mesh(), truth, whole);
  const int rows = static_cast<int>(projectPoint(truth, {form.axisXCm(), cutCm, 0}).y());
  const cv::Mat3b cut = scene(cv::Rect(0, 0, whole.width, rows)).clone();
  const Registration reg = registerForm(form, cut, name, options);
  EXPECT_NEAR(reg.pose.pxPerCm / truth.pxPerCm, 1.0, 0.004) << name;
  EXPECT_GT(reg.iou, 0.97) << name;
  EXPECT_TRUE(reg.frameBottomCm.has_value()) << name;
  if (reg.frameBottomCm) {
    EXPECT_NEAR(*reg.frameBottomCm, cutCm, 0.5) << name;
  }
  // Landmarks in view where the truth puts them.
  const auto expected = landmarkPoints(form, truth);
  EXPECT_EQ(expected.size(), reg.landmarks.size());
  for (std::size_t i = 0; i < std::min(expected.size(), reg.landmarks.size()); ++i)
    if (expected[i].second.y() < rows) {
      EXPECT_LT((expected[i].second - reg.landmarks[i].second).norm(), 1.5)
          << name << " " << expected[i].first;
    }
  // The calibration carries the cut through JSON.
  const Calibration c = calibrationFromJson(
      nlohmann::json::parse(calibrationToJson(makeCalibration(form, reg, "f.json", "e.png", {}))),
      name);
  EXPECT_EQ(c.frameBottomCm.has_value(), reg.frameBottomCm.has_value());
  ::testing::Test::RecordProperty(std::string(name) + "_px_per_cm_error",
                                  std::to_string(reg.pose.pxPerCm / truth.pxPerCm - 1));
  return reg.pose.pxPerCm / truth.pxPerCm - 1;
}

TEST(RegistrationCutAtBottom, LegsOutOfFrame) {
  const FormModel& form = test::realForm();
  registerCut(form, 40.0, false, "knees");
  registerCut(form, 10.0, false, "ankles");
  // Cut this near the hip, the part in view (arms out) is about as wide as it is tall and its
  // principal axis gives no roll: the roll is not fitted there (docs/calibration.md), so the
  // scene has none.
  registerCut(form, *form.landmarks().hip - 12.0, false, "thighs", 0.0);
  registerCut(test::parametricForm55(), 45.0, true, "perspective");
}

TEST(RegistrationCutAtBottom, AboveTheHipIsRefused) {
  const FormModel& form = test::realForm();
  const cv::Size whole(1000, 900);
  FormPose truth;
  truth.pxPerCm = 0.9 * whole.height / form.heightCm();
  truth.offsetPx = {0.5 * whole.width, 0.95 * whole.height};
  const cv::Mat3b scene = test::makeScene(form.mesh(), truth, whole);
  const int rows = static_cast<int>(projectPoint(truth, {0, *form.landmarks().hip + 3.0, 0}).y());
  try {
    registerForm(form, scene(cv::Rect(0, 0, whole.width, rows)).clone(), "frame");
    ADD_FAILURE() << "a form cut above its hip registered";
  } catch (const CalibError& e) {
    EXPECT_EQ(e.kind(), CalibErrorKind::kFormCutOff);
    EXPECT_NE(std::string(e.what()).find("hip"), std::string::npos) << e.what();
  }
  // Without the option a cut at the bottom is refused as before.
  RegistrationOptions strict;
  strict.key.allowCutAtBottom = false;
  const int knees = static_cast<int>(projectPoint(truth, {0, 40.0, 0}).y());
  try {
    registerForm(form, scene(cv::Rect(0, 0, whole.width, knees)).clone(), "frame", strict);
    ADD_FAILURE() << "allowCutAtBottom = false did not refuse";
  } catch (const CalibError& e) {
    EXPECT_EQ(e.kind(), CalibErrorKind::kFormCutOff);
    EXPECT_NE(std::string(e.what()).find("bottom"), std::string::npos) << e.what();
  }
}

CalibErrorKind kindOf(const cv::Mat3b& frame) {
  try {
    registerForm(test::parametricForm55(), frame, "frame");
  } catch (const CalibError& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no CalibError";
  return CalibErrorKind::kMeshNotClosed;
}

TEST(RegistrationBadInput, EachWithItsOwnError) {
  const cv::Size size(480, 320);
  const FormModel& form = test::parametricForm55();
  FormPose pose;
  pose.pxPerCm = 0.85 * size.height / form.heightCm();
  pose.offsetPx = {240, 0.925 * size.height};

  // No form: only the screen.
  FormPose away = pose;
  away.offsetPx = {-5000, -5000};
  EXPECT_EQ(kindOf(test::makeScene(form.mesh(), away, size)), CalibErrorKind::kNoFormInFrame);

  // Cut off: the head leaves the top of the frame.
  FormPose high = pose;
  high.offsetPx.y() -= 0.15 * size.height;
  EXPECT_EQ(kindOf(test::makeScene(form.mesh(), high, size)), CalibErrorKind::kFormCutOff);

  // Not a green screen: a grey wall, then a blue screen.
  test::SceneStyle grey;
  grey.screenBgr = {128, 130, 126};
  EXPECT_EQ(kindOf(test::makeScene(form.mesh(), pose, size, grey)),
            CalibErrorKind::kNotGreenScreen);
  test::SceneStyle blue;
  blue.screenBgr = {200, 90, 40};
  EXPECT_EQ(kindOf(test::makeScene(form.mesh(), pose, size, blue)),
            CalibErrorKind::kNotGreenScreen);

  // Something that is not the form: a box in front of the screen.
  cv::Mat3b box = test::makeScene(form.mesh(), away, size);
  cv::rectangle(box, cv::Rect(150, 40, 180, 240), cv::Scalar(150, 160, 200), cv::FILLED);
  EXPECT_EQ(kindOf(box), CalibErrorKind::kFitFailed);
}

TEST(Registration, KeyerUnmixesEdgesAndSuppressesSpill) {
  const cv::Size size(400, 300);
  const FormModel& form = test::parametricForm55();
  FormPose pose;
  pose.pxPerCm = 0.85 * size.height / form.heightCm();
  pose.offsetPx = {200.3, 0.925 * size.height};
  const cv::Mat1f cov = renderCoverage(form.mesh(), pose, size, 8);
  const KeyResult key = keyGreenScreen(test::makeScene(form.mesh(), pose, size), "scene");
  // Coverage area (the scale is its square root) to 0.5%: 0.25% in px/cm at this small size.
  const double areaRatio = cv::sum(key.alpha)[0] / cv::sum(cov)[0];
  EXPECT_NEAR(areaRatio, 1.0, 0.005);
  ::testing::Test::RecordProperty("keyed_area_ratio", std::to_string(areaRatio));
  // No foreground pixel keeps more green than red or blue after despill.
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      if (key.alpha(y, x) > 0.05f) {
        const cv::Vec3b p = key.despilled(y, x);
        ASSERT_LE(p[1], std::max(p[0], p[2]));
      }
    }
  }
}

TEST(Registration, CalibrationJsonRoundTrip) {
  const cv::Size size(480, 320);
  const FormModel& form = test::parametricForm55();
  FormPose pose;
  pose.pxPerCm = 0.85 * size.height / form.heightCm();
  pose.offsetPx = {240, 0.925 * size.height};
  const Registration reg = registerForm(form, test::makeScene(form.mesh(), pose, size), "scene");
  const Calibration c = makeCalibration(form, reg, "form.json", "empty.png", std::nullopt);
  const fs::path p =
      fs::temp_directory_path() / ("garmcap_calib_" + std::to_string(::getpid()) + ".json");
  writeCalibration(p, c);
  const Calibration back = readCalibration(p);
  EXPECT_NEAR(back.pose.pxPerCm, c.pose.pxPerCm, 1e-4);
  EXPECT_NEAR(back.pose.offsetPx.x(), c.pose.offsetPx.x(), 1e-4);
  EXPECT_EQ(back.landmarks.size(), c.landmarks.size());
  EXPECT_EQ(back.imageSize, size);
  EXPECT_FALSE(back.camera.has_value());
  EXPECT_EQ(back.landmarkHeightsCm.size(), form.landmarks().toMap().size());
  fs::remove(p);
}

}  // namespace
}  // namespace garmcap::calib
