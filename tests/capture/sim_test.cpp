// Scene simulator: determinism, the garment width model the pipeline inverts, lengths, and
// refusals. Images are small (<= 0.3 MP) to keep the suite fast under sanitizers.
#include "garmcap/sim/sim.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "garmcap/calib/form_model.h"
#include "garmcap/sim/scene.h"

namespace garmcap::sim {

using sim::garmentMeasurementNames;
namespace {

const std::string kForm =
    std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";

const calib::FormModel& form() {
  static const auto f = std::make_unique<calib::FormModel>(calib::FormModel::load(kForm));
  return *f;
}

Scene sceneOf(const std::string& type, std::uint64_t seed, cv::Size size = {360, 480}) {
  RandomSceneOptions o;
  o.size = size;
  o.type = type;
  o.hardFraction = 0;
  return randomScene(form(), kForm, seed, o);
}

// Garment span [first, last] covered (> 0) in one image row around the axis (arms apart from
// the body are excluded by walking out from the axis), and its sub-pixel width (coverage sum).
struct Span {
  int first, last;
  double widthPx;
};
Span spanAround(const cv::Mat1f& cov, int row, int axis) {
  int l = axis, r = axis;
  while (l > 0 && cov(row, l - 1) > 0.f)
    --l;
  while (r + 1 < cov.cols && cov(row, r + 1) > 0.f)
    ++r;
  double w = 0;
  for (int x = l; x <= r; ++x)
    w += cov(row, x);
  return {l, r, w};
}

TEST(Simulator, DeterministicFromSeedAndNoiseDiffersBetweenShots) {
  const SceneRenderer a(form(), sceneOf("dress", 3));
  const SceneRenderer b(form(), sceneOf("dress", 3));
  const cv::Mat ea = a.renderEmpty(), eb = b.renderEmpty();
  EXPECT_EQ(cv::norm(ea, eb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.renderDressed(), b.renderDressed(), cv::NORM_INF), 0.0);
  const SceneRenderer c(form(), sceneOf("dress", 4));
  EXPECT_GT(cv::norm(ea, c.renderEmpty(), cv::NORM_L1), 0.0);
}

TEST(Simulator, BareFrameIsAFormOnAGreenScreen) {
  const SceneRenderer r(form(), sceneOf("top", 5));
  const cv::Mat img = r.renderEmpty();
  ASSERT_EQ(img.size(), cv::Size(360, 480));
  // Corners: green dominates.
  for (const cv::Point p :
       {cv::Point(3, 3), cv::Point(356, 3), cv::Point(3, 476), cv::Point(356, 476)}) {
    const cv::Vec3b c = img.at<cv::Vec3b>(p);
    EXPECT_GT(c[1], c[0] + 20) << p;
    EXPECT_GT(c[1], c[2] + 20) << p;
  }
  // The form's centre (waist height) is not green.
  const auto& v = r.view();
  const cv::Vec3b f = img.at<cv::Vec3b>(static_cast<int>(v.rowOfHeight(v.waistCm())),
                                        static_cast<int>(v.axisXPx()));
  EXPECT_GT(f[2], f[1] - 25);
}

// The garments hang (docs/simulator.md, "Width model"): over the hip, and at a skirt's or
// pants' waist, the section is the form's own grown by a uniform ease e, so its round is the
// form's tape + 2 pi e and its width the form's + 2 e (Steiner's formula for a convex section):
// C = C_ref + pi * (W_garment - W_ref) at every row of the measurement's plateau. A bodice's waist
// puts part of its ease into depth (its front and back hang off the bust), so there the same
// formula reads at most the truth, and the garment is never narrower than the form.
TEST(Simulator, GarmentWidthFollowsAUniformEaseOverTheHip) {
  for (const std::string type : {"top", "dress", "skirt", "pants"}) {
    for (std::uint64_t seed : {11, 12}) {
      const SceneRenderer r(form(), sceneOf(type, seed, {600, 800}));
      const auto& v = r.view();
      const double s = v.pose().pxPerCm;
      const cv::Mat1f cov = r.garmentCoverage();
      const auto& m = r.scene().garment.measurements;
      const bool bodice = type == "top" || type == "dress";
      std::vector<std::pair<std::string, double>> knots = {{"waist_circ", v.waistCm()}};
      if (type != "top")
        knots.push_back({"hip_circ", v.hipCm()});
      for (const auto& [name, h] : knots) {
        // Read at the landmark and 1 cm off it (the plateau absorbs landmark disagreement).
        for (const double dh : {0.0, 1.0, -1.0}) {
          const int row = static_cast<int>(std::lround(v.rowOfHeight(h + dh)));
          // Below the hip the reference section is the hip's (docs/simulator.md).
          const auto form = h + dh < v.hipCm() ? v.torsoAtHeight(v.hipCm()) : v.torsoAtRow(row);
          ASSERT_TRUE(form) << type << " " << name;
          const Span sp = spanAround(cov, row, static_cast<int>(std::lround(form->centrePx())));
          const double circ = form->circCm + std::numbers::pi * (sp.widthPx - form->widthPx()) / s;
          const std::string where =
              type + " seed " + std::to_string(seed) + " " + name + " dh " + std::to_string(dh);
          EXPECT_GE(sp.widthPx, form->widthPx()) << where;
          if (bodice && name == "waist_circ")
            EXPECT_LE(circ, m.at(name) + 0.15) << where;
          else
            EXPECT_NEAR(circ, m.at(name), 0.15) << where;
        }
      }
    }
  }
}

TEST(Simulator, LengthsMatchTheTruth) {
  for (std::uint64_t seed : {21, 22, 23}) {
    const SceneRenderer r(form(), sceneOf("dress", seed, {600, 800}));
    const auto& v = r.view();
    const cv::Mat1f cov = r.garmentCoverage();
    int top = -1;
    for (int y = 0; y < cov.rows && top < 0; ++y) {
      for (int x = 0; x < cov.cols; ++x) {
        if (cov(y, x) > 0.5f) {
          top = y;
          break;
        }
      }
    }
    const int axis = static_cast<int>(std::lround(v.axisXPx()));
    int hem = 0;
    for (int y = 0; y < cov.rows; ++y) {
      if (cov(y, axis) > 0.5f)
        hem = y;
    }
    const auto& m = r.scene().garment.measurements;
    const double s = r.scene().pose.pxPerCm;
    EXPECT_NEAR((hem - top + 1) / s, m.at("garment_length"), 1.5 / s + 0.1) << seed;
    EXPECT_NEAR((hem + 0.5 - v.rowOfHeight(v.waistCm())) / s, m.at("skirt_length"), 1.0 / s + 0.1)
        << seed;
  }
}

TEST(Simulator, PantsShowTheCrotchAtInseamAboveTheHem) {
  const SceneRenderer r(form(), sceneOf("pants", 31, {600, 800}));
  const auto& v = r.view();
  const cv::Mat1f cov = r.garmentCoverage();
  const int axis = static_cast<int>(std::lround(v.axisXPx()));
  int lastCovered = -1;
  for (int y = 0; y < cov.rows; ++y) {
    if (cov(y, axis) > 0.5f)
      lastCovered = y;
  }
  const auto& m = r.scene().garment.measurements;
  const double s = r.scene().pose.pxPerCm;
  const double crotchRow = v.rowOfHeight(v.waistCm() - m.at("outseam") + m.at("inseam"));
  EXPECT_NEAR(lastCovered + 0.5, crotchRow, 1.0);
  // Both legs reach the hem, left and right of the axis.
  const int hemRow =
      static_cast<int>(std::lround(v.rowOfHeight(v.waistCm() - m.at("outseam") + 2.0)));
  int left = 0, right = 0;
  for (int x = 0; x < cov.cols; ++x) {
    if (cov(hemRow, x) > 0.5f)
      (x < axis ? left : right)++;
  }
  EXPECT_GT(left, static_cast<int>(5 * s));
  EXPECT_GT(right, static_cast<int>(5 * s));
}

TEST(Simulator, SleeveEndsAtSleeveLengthAlongTheArm) {
  for (const std::uint64_t seed : {41, 42, 43, 44, 45, 46}) {
    Scene sc = sceneOf("top", seed, {600, 800});
    if (sc.garment.attributes["sleeve"] == "none")
      continue;
    const SceneRenderer r(form(), sc);
    const cv::Mat1f cov = r.garmentCoverage();
    const double s = sc.pose.pxPerCm;
    const double L = sc.garment.measurements.at("sleeve_length") * s;
    for (int side = 0; side < 2; ++side) {
      const auto& arm = r.view().arm(side);
      ASSERT_TRUE(arm);
      // Points on the arm's centre line, t px down the arm from the shoulder tip.
      const Eigen::Vector2d normal(arm->dir.y(), -arm->dir.x());
      auto at = [&](double t) -> cv::Point {
        const Eigen::Vector2d p = arm->originPx + arm->dir * t + normal * arm->centreAt(t);
        return {static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))};
      };
      EXPECT_GT(cov(at(L - 2)), 0.5f) << seed << " side " << side;
      const cv::Point beyond = at(L + 2);
      const Span body =
          spanAround(cov, beyond.y, static_cast<int>(std::lround(r.view().axisXPx())));
      if (beyond.x < body.first || beyond.x > body.last) {
        EXPECT_LT(cov(beyond), 0.5f) << seed << " side " << side;
      }
    }
  }
}

TEST(Simulator, RefusesAGarmentSmallerThanTheForm) {
  Scene sc = sceneOf("skirt", 51);
  sc.garment.measurements["waist_circ"] = 60;
  try {
    SceneRenderer r(form(), sc);
    FAIL() << "a 60 cm waist on an 80 cm form was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("waist_circ 60.0"), std::string::npos) << e.what();
  }
}

TEST(Simulator, RefusesMoreThanTwelveMegapixels) {
  Scene sc = sceneOf("skirt", 52);
  sc.size = {4000, 3001};
  EXPECT_THROW(SceneRenderer(form(), sc), std::invalid_argument);
}

TEST(Simulator, SceneJsonRoundTripRendersTheSameFrames) {
  const Scene sc = sceneOf("top", 61);
  const Scene back = Scene::fromJson(sc.toJson(), "scene");
  const SceneRenderer a(form(), sc), b(form(), back);
  EXPECT_EQ(cv::norm(a.renderDressed(), b.renderDressed(), cv::NORM_INF), 0.0);
  nlohmann::json bad = sc.toJson();
  bad["lighting"]["colour"] = 1;
  EXPECT_THROW(Scene::fromJson(bad, "scene"), std::exception);
}

TEST(Simulator, TruthHasTheMeasurementsOfTheType) {
  for (const std::string type : {"top", "dress", "skirt", "pants"}) {
    const SceneRenderer r(form(), sceneOf(type, 71));
    const auto t = r.truth();
    EXPECT_EQ(t["type"], type);
    EXPECT_EQ(t["measurements"].size(), garmentMeasurementNames(type).size());
    for (const auto& n : garmentMeasurementNames(type))
      EXPECT_TRUE(t["measurements"].contains(n)) << n;
    EXPECT_TRUE(t["calibration"].contains("pose"));
  }
}

}  // namespace
}  // namespace garmcap::sim
