// A torso dress form on a stand (neck cap, no head, arms or legs; a pole and a foot): its
// landmarks, measurements and registration. The forms come from the generator's torso variant;
// the calibration is given the mesh only (an empty sidecar), and is checked against the
// generator's own stations, which it never reads.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "garmcap/calib/errors.h"
#include "garmcap/calib/form_view.h"
#include "garmcap/calib/registration.h"
#include "synthetic_scene.h"
#include "test_forms.h"

namespace garmcap::calib {
namespace {

FormModel torsoForm(const sim::ParametricForm& pf) {
  return FormModel(pf.mesh(), FormSidecar{});  // no sidecar: nothing of the inputs is read
}

TEST(TorsoForm, LandmarksAgainstTheGeneratorsStations) {
  for (const char* size : {"44", "55", "77"}) {
    SCOPED_TRACE(std::string("size ") + size);
    const auto body = test::table42(size);
    const sim::ParametricForm pf(body, sim::FormKind::kTorso);
    const FormModel form = torsoForm(pf);
    const auto& st = pf.stationHeights();
    const auto& lm = form.landmarks();
    EXPECT_TRUE(form.isTorsoForm());
    EXPECT_FALSE(lm.crotch.has_value());
    EXPECT_FALSE(form.measurements().has("leg_crotch_to_floor"));
    // No stature: the form's height is its stand's, not a body's.
    EXPECT_FALSE(form.measurements().has("height"));
    EXPECT_FALSE(pf.sidecar("torso.obj").measurements.has("height"));
    // The flat bottom of the torso, found above the pole and the foot.
    EXPECT_NEAR(form.torsoBottomCm(), st.at("crotch"), 0.1);
    EXPECT_NEAR(form.heightCm(), st.at("top"), 0.01);
    // Girth extrema: the stations are the extrema of the generator's girth curve.
    ASSERT_TRUE(lm.bust && lm.waist && lm.hip && lm.armpit && lm.shoulder && lm.neckBase);
    EXPECT_NEAR(*lm.bust, st.at("bust"), 0.5);
    EXPECT_NEAR(*lm.waist, st.at("waist"), 0.5);
    EXPECT_NEAR(*lm.hip, st.at("hip"), 0.5);
    for (const char* m : {"bust_circ", "waist_circ", "hip_circ"})
      EXPECT_NEAR(form.measurements().get(m), body.get(m), 0.003 * body.get(m)) << m;
    // Shape landmarks (docs/calibration.md "Torso forms"): defined by the form's outline, so
    // they sit near, not on, the generator's stations.
    EXPECT_NEAR(*lm.shoulder, st.at("shoulder"), 2.5);
    EXPECT_NEAR(*lm.neckBase, st.at("neck_base"), 1.5);
    EXPECT_NEAR(*lm.armpit, st.at("armpit"), 1.5);
    EXPECT_LT(*lm.bust, *lm.armpit);
    EXPECT_LT(*lm.armpit, *lm.shoulder);
    EXPECT_LT(*lm.shoulder, *lm.neckBase);
  }
}

// No arms are found on a torso form (its stand's foot once read as two).
TEST(TorsoForm, ViewHasNoArms) {
  for (const char* size : {"44", "55", "77"}) {
    const sim::ParametricForm pf(test::table42(size), sim::FormKind::kTorso);
    const FormModel form = torsoForm(pf);
    FormPose pose;
    pose.pxPerCm = 0.9 * 800 / form.heightCm();
    pose.offsetPx = {300, 0.95 * 800};
    const FormView view(form, pose, {600, 800});
    EXPECT_FALSE(view.arm(0).has_value()) << size;
    EXPECT_FALSE(view.arm(1).has_value()) << size;
    EXPECT_FALSE(view.crotchCm().has_value()) << size;
  }
}

TEST(TorsoForm, FullMannequinIsNotATorso) {
  const FormModel& full = test::parametricForm55();
  EXPECT_FALSE(full.isTorsoForm());
  EXPECT_TRUE(full.landmarks().crotch.has_value());
}

TEST(TorsoForm, SidecarOfTheGeneratorAgrees) {
  const sim::ParametricForm pf(test::table42("55"), sim::FormKind::kTorso);
  EXPECT_NO_THROW(FormModel(pf.mesh(), pf.sidecar("torso.obj")));
}

// Registration of the torso with its pole and foot, whole and with the pole cut by the frame.
TEST(TorsoForm, Registration) {
  const sim::ParametricForm pf(test::table42("55"), sim::FormKind::kTorso);
  const FormModel form = torsoForm(pf);
  const cv::Size size(900, 1200);
  for (const bool cut : {false, true}) {
    SCOPED_TRACE(cut ? "pole cut by the frame" : "whole stand in view");
    FormPose truth;
    truth.pxPerCm = 0.85 * size.height / form.heightCm();
    truth.offsetPx = {0.52 * size.width, 0.93 * size.height + 0.3};
    truth.rollRad = 0.01;
    cv::Mat3b scene = test::makeScene(form.mesh(), truth, size);
    if (cut) {
      const int rows = static_cast<int>(projectPoint(truth, {form.axisXCm(), 50.0, 0}).y());
      scene = scene(cv::Rect(0, 0, size.width, rows)).clone();
    }
    const Registration reg = registerForm(form, scene, "torso");
    EXPECT_NEAR(reg.pose.pxPerCm / truth.pxPerCm, 1.0, 0.003);
    EXPECT_GT(reg.iou, 0.98);
    EXPECT_EQ(reg.frameBottomCm.has_value(), cut);
    const auto expected = landmarkPoints(form, truth);
    ASSERT_EQ(expected.size(), reg.landmarks.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
      EXPECT_LT((expected[i].second - reg.landmarks[i].second).norm(), 1.5) << expected[i].first;
  }
}

// The stand's foot in a dark floor shadow that keys as form: the fit is made on the torso.
TEST(TorsoForm, RegistrationIgnoresTheFootsShadow) {
  const sim::ParametricForm pf(test::table42("55"), sim::FormKind::kTorso);
  const FormModel form = torsoForm(pf);
  const cv::Size size(900, 1200);
  FormPose truth;
  truth.pxPerCm = 0.85 * size.height / form.heightCm();
  truth.offsetPx = {0.5 * size.width, 0.93 * size.height};
  cv::Mat3b scene = test::makeScene(form.mesh(), truth, size);
  const Eigen::Vector2d foot = projectPoint(truth, {0, 0, 0});
  cv::ellipse(scene, cv::Point(static_cast<int>(foot.x()), static_cast<int>(foot.y())),
              cv::Size(static_cast<int>(22 * truth.pxPerCm), static_cast<int>(3 * truth.pxPerCm)),
              0, 0, 360, cv::Scalar(40, 45, 40), cv::FILLED);
  const Registration reg = registerForm(form, scene, "torso in shadow");
  EXPECT_NEAR(reg.pose.pxPerCm / truth.pxPerCm, 1.0, 0.003);
  const auto expected = landmarkPoints(form, truth);
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_LT((expected[i].second - reg.landmarks[i].second).norm(), 1.5) << expected[i].first;
}

TEST(TorsoForm, ArmlessFormWithoutNeckIsRefused) {
  // A plain column (a closed box): no arms, no shoulders or neck above a torso.
  TriMesh box;
  box.vertices = {{-15, 0, -10},   {15, 0, -10},   {15, 0, 10},   {-15, 0, 10},
                  {-15, 100, -10}, {15, 100, -10}, {15, 100, 10}, {-15, 100, 10}};
  box.faces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
               {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  try {
    FormModel f(box, FormSidecar{});
    ADD_FAILURE() << "a box was taken for a form";
  } catch (const CalibError& e) {
    EXPECT_EQ(e.kind(), CalibErrorKind::kFormNotRecognised) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::calib
