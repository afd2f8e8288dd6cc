// The pipeline segments on a downscaled work frame and returns the outline to full resolution;
// these tests render scenes with the simulator and hold that path to the full-resolution one and
// to the rendered truth, and check the skirt-or-pants decision by parted legs. Label "rig".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/bundled_form.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_guide.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/garment_measurer.h"
#include "garmcap/pipeline/grabcut_refine.h"
#include "garmcap/sim/garment_model.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

using namespace garmcap;

namespace {

const std::string& kFormPath = garmcap::testing::bundledFormPath();

const calib::FormModel& form() {
  return garmcap::testing::bundledForm();
}

sim::SceneRenderer scene(const std::string& type, unsigned seed, cv::Size size) {
  sim::RandomSceneOptions o;
  o.size = size;
  o.hardFraction = 0;
  o.type = type;
  return sim::SceneRenderer(form(), sim::randomScene(form(), kFormPath, seed, o));
}

pipeline::CaptureOptions measureOnly(double workMegapixels) {
  pipeline::CaptureOptions o;
  o.makeProductImages = false;
  o.makeTexture = false;
  o.workMegapixels = workMegapixels;
  return o;
}

}  // namespace

// Pants part into two legs below the hip for far more than the 5 cm threshold; skirts and
// dresses cover the centre line to the hem and do not part at all. On the rendered coverage,
// so this checks the rule, not the segmentation.
TEST(PartedLegs, PantsPartSkirtsAndDressesDoNot) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (const std::string type : {"pants", "skirt", "dress"}) {
      const sim::SceneRenderer r = scene(type, seed, {480, 640});
      const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
      const cv::Mat mask = r.garmentCoverage() > 0.5f;
      const double cm = pipeline::partedLegsCm(mask, *ctx->view);
      if (type == "pants")
        EXPECT_GT(cm, 15.0) << type << " seed " << seed;
      else
        EXPECT_LT(cm, 1.0) << type << " seed " << seed;
    }
  }
}

TEST(PartedLegs, RejectsAMaskOfTheWrongSize) {
  const sim::SceneRenderer r = scene("pants", 1, {480, 640});
  const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
  EXPECT_THROW(pipeline::partedLegsCm(cv::Mat::zeros(10, 10, CV_8UC1), *ctx->view),
               std::invalid_argument);
}

// A 2 MP frame segmented on a 1 MP work frame (the default's ratio at 4 MP) against the same
// frame segmented at full resolution, over eight scenes each of dresses and pants (seeds 1-8).
// One scene says little: on a dark checked pair the two paths' IoU differ by up to 0.008 either
// way, and which one wins flips with any change to the scene (seed 5: work frame 0.9893 / full
// 0.9845, then 0.9812 / 0.9894 with the pants' lower legs drawn 10 % narrower; seed 4 0.9871 /
// 0.9924). So each scene holds the silhouette within 0.97 IoU of the rendered truth and within
// 0.01 of the full frame's, each reading within 1.5 cm of the full frame's distance from the
// truth, and on average over the scenes the work frame is as close as the full frame: IoU within
// 0.002, readings within 0.2 cm.
TEST(WorkFrame, AsAccurateAsFullResolutionSegmentation) {
  double iouGapSum = 0, readingGapSum = 0;
  int scenes = 0, readings = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    for (const std::string type : {"dress", "pants"}) {
      const sim::SceneRenderer r = scene(type, seed, {1224, 1632});
      const cv::Mat empty = r.renderEmpty(), dressed = r.renderDressed();
      const auto cal = r.calibration();
      const auto small = pipeline::runCapture(empty, dressed, cal, measureOnly(1.0));
      const auto full = pipeline::runCapture(empty, dressed, cal, measureOnly(100.0));
      const std::string what = type + " seed " + std::to_string(seed);
      EXPECT_EQ(small.type, type) << what;
      EXPECT_EQ(full.type, type) << what;
      ASSERT_EQ(small.silhouette.size(), empty.size()) << what;
      const cv::Mat truth = r.garmentCoverage() > 0.5f;
      const double iouSmall = pipeline::maskIou(small.silhouette, truth);
      const double iouFull = pipeline::maskIou(full.silhouette, truth);
      EXPECT_GT(iouSmall, 0.97) << what;
      EXPECT_GT(iouSmall, iouFull - 0.01) << what;
      iouGapSum += iouFull - iouSmall;
      ++scenes;
      const nlohmann::json expected = r.truth().at("measurements");
      ASSERT_EQ(small.measurements.size(), full.measurements.size()) << what;
      for (const auto& [name, v] : full.measurements) {
        ASSERT_TRUE(small.measurements.count(name)) << what << " " << name;
        ASSERT_TRUE(expected.contains(name)) << what << " " << name;
        const double t = expected.at(name).get<double>();
        const double gap = std::abs(small.measurements.at(name) - t) - std::abs(v - t);
        EXPECT_LE(gap, 1.5) << what << " " << name << ": work frame " << small.measurements.at(name)
                            << ", full resolution " << v << ", truth " << t;
        readingGapSum += gap;
        ++readings;
      }
    }
  }
  ASSERT_GT(scenes, 0);
  ASSERT_GT(readings, 0);
  std::printf(
      "work frame against full resolution, %d scenes: IoU %.4f lower, readings %.3f cm "
      "further from the truth, on average\n",
      scenes, iouGapSum / scenes, readingGapSum / readings);
  EXPECT_LE(iouGapSum / scenes, 0.002);
  EXPECT_LE(readingGapSum / readings, 0.2);
}

// Hard scenes (fabric the colour of the form or dark green, camera shake, strong spill). History:
// before the noise-floor exposed test and the sure-form rule, form-coloured tops read as dresses
// with the whole torso and hems were 40-90 cm off; with them, 5 of these 10 scenes were typed and
// the rest came out "unknown" or "no garment" (dark green keys as screen), and a form-coloured
// sleeve's end was up to 7 cm off. With the bare-frame comparison for screen-coloured garments,
// re-registration that also reads the camera's roll, and the clearly-exposed rule, every scene
// is typed and every measurement is within 1.5 cm.
TEST(WorkFrame, HardScenesAreTypedAndMeasured) {
  for (const std::string type : {"top", "pants"}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      sim::RandomSceneOptions o;
      o.size = {960, 1280};
      o.hardFraction = 1.0;
      o.type = type;
      const sim::SceneRenderer r(form(), sim::randomScene(form(), kFormPath, seed, o));
      const std::string where = type + " seed " + std::to_string(seed);
      const auto res = pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(),
                                            measureOnly(2.0));
      ASSERT_EQ(res.type, type) << where;
      const nlohmann::json expected = r.truth().at("measurements");
      // Every measurement of the truth, so that one left out fails instead of passing.
      for (const auto& [name, t] : expected.items()) {
        const auto it = res.measurements.find(name);
        if (it == res.measurements.end()) {
          ADD_FAILURE() << where << " " << name << " is missing";
          continue;
        }
        const double err = it->second - t.get<double>();
        EXPECT_LE(std::abs(err), 1.5)
            << where << " " << name << " measured " << it->second << " truth " << t;
      }
    }
  }
}

// On a form whose legs nearly touch (the generated korean_women_55), wide pants legs meet between
// the form's legs and their inner edges flatten against each other; the leg opening comes from
// the outer halves there (the run's width alone read 9-11 cm small on these three scenes).
TEST(WorkFrame, LegOpeningOnAFormWhoseLegsNearlyTouch) {
  const std::string path = std::string(GARMCAP_TEST_DATA_DIR) + "/forms/korean_women_55.json";
  const calib::FormModel narrow = calib::FormModel::load(path);
  for (const unsigned seed : {3u, 7u, 11u}) {
    sim::RandomSceneOptions o;
    o.size = {960, 1280};
    o.hardFraction = 0;
    o.type = "pants";
    const sim::SceneRenderer r(narrow, sim::randomScene(narrow, path, seed, o));
    const auto res =
        pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(), measureOnly(2.0));
    ASSERT_EQ(res.type, "pants") << "seed " << seed;
    ASSERT_TRUE(res.measurements.count("leg_opening_circ")) << "seed " << seed;
    const double truth = r.truth().at("measurements").at("leg_opening_circ").get<double>();
    EXPECT_NEAR(res.measurements.at("leg_opening_circ"), truth, 1.5) << "seed " << seed;
  }
}

// On a form with broad shoulder caps (the generated korean_women_55) a sleeveless bodice covers
// about 7 cm of the arm from the calibrated shoulder tip, and read as a short sleeve: 3-7 cm on
// seeds 12, 23 and 27 here (and 2 of 12 tops on a 4 MP holdout rig). The edge that ends the
// cover runs from the shoulder toward the underarm there, not across the arm as a sleeve's hem
// (docs/measurement_model.md, "Sleeve or armhole"); short sleeves stay short.
TEST(WorkFrame, SleevelessOnAFormWithBroadShoulders) {
  const std::string path = std::string(GARMCAP_TEST_DATA_DIR) + "/forms/korean_women_55.json";
  const calib::FormModel broad = calib::FormModel::load(path);
  sim::RandomSceneOptions o;
  o.size = {960, 1280};
  o.hardFraction = 0;
  o.type = "top";
  std::vector<unsigned> seeds = {12, 23, 27};
  for (unsigned seed = 1, shortSleeves = 0; shortSleeves < 2 && seed < 100; ++seed)
    if (sim::randomScene(broad, path, seed, o).garment.attributes.at("sleeve") == "short") {
      seeds.push_back(seed);
      ++shortSleeves;
    }
  ASSERT_EQ(seeds.size(), 5u);
  for (const unsigned seed : seeds) {
    const sim::SceneRenderer r(broad, sim::randomScene(broad, path, seed, o));
    const auto res =
        pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(), measureOnly(2.0));
    ASSERT_EQ(res.type, "top") << "seed " << seed;
    EXPECT_EQ(res.attributes.at("sleeve"), r.truth().at("attributes").at("sleeve")) << seed;
    const double length = r.truth().at("measurements").at("sleeve_length").get<double>();
    EXPECT_NEAR(res.measurements.at("sleeve_length"), length, 1.5) << "seed " << seed;
  }
}

// A garment cannot measure much less round than the form it is worn on: where the silhouette
// lost part of the garment's side (the garment ends inside the form's outline, as a
// form-coloured patch reaching the edge leaves), the circumference there is left out with a
// warning, not reported small; the rest still measures, and the hem line is not lifted by the
// cut. A slit with garment on both sides of it inside the form's outline is a hole the garment
// spans (a tube round the form): it is bridged and the hem reads as before.
TEST(Measure, ACircumferenceFarBelowTheFormsIsLeftOutNotInvented) {
  const sim::SceneRenderer r = scene("top", 2, {720, 960});
  const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
  const calib::FormView& view = *ctx->view;
  const cv::Mat full = r.garmentCoverage() > 0.5f;
  const auto intact = pipeline::measureGarment(full, view, "top");
  ASSERT_TRUE(intact.measurements.count("hem_circ"));

  // A slit 1.5 cm wide, 1 cm right of the centre front, from the hem 5 cm up: bridged.
  cv::Mat slit = full.clone();
  const cv::Rect box = cv::boundingRect(full);
  const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  const int bottom = box.y + box.height;
  const cv::Range hemBand(bottom - static_cast<int>(5 * s), bottom);
  slit(hemBand, cv::Range(axis + static_cast<int>(s), axis + static_cast<int>(2.5 * s))).setTo(0);
  const auto bridged = pipeline::measureGarment(slit, view, "top");
  ASSERT_TRUE(bridged.measurements.count("hem_circ"));
  EXPECT_NEAR(bridged.measurements.at("hem_circ"), intact.measurements.at("hem_circ"), 0.3);

  // The same band cut from 1 cm right of the centre front out past the garment's side: the
  // garment is on one side of the centre only there, and its run is about half the form's.
  cv::Mat notched = full.clone();
  notched(hemBand, cv::Range(axis + static_cast<int>(s), box.x + box.width)).setTo(0);
  const auto cut = pipeline::measureGarment(notched, view, "top");
  EXPECT_FALSE(cut.measurements.count("hem_circ"))
      << "hem_circ " << cut.measurements.at("hem_circ") << " reported";
  bool warned = false;
  for (const auto& w : cut.warnings)
    warned |=
        w.find("hem_circ") != std::string::npos && w.find("not measured") != std::string::npos;
  EXPECT_TRUE(warned);
  for (const std::string name : {"bust_circ", "waist_circ", "garment_length"})
    EXPECT_NEAR(cut.measurements.at(name), intact.measurements.at(name), 0.3) << name;
}

// A skirt or dress is one tube round both legs below the torso too: a narrow notch the
// segmentation leaves up from its hem beside the centre front (rig N case_010, rig H case_005:
// a near-screen-coloured hem over the screen between the legs, notches 0.1-1 cm wide and 1-2 cm
// deep) is bridged, and the hem reads as the intact silhouette's, not as the piece on one side
// of the notch (13 and 81 cm round, dropped as "part of the garment is missing").
TEST(Measure, ANotchUpFromASkirtsHemIsBridged) {
  for (const std::string type : {"skirt", "dress"}) {
    for (unsigned seed = 1; seed <= 2; ++seed) {
      const sim::SceneRenderer r = scene(type, seed, {720, 960});
      const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
      const calib::FormView& view = *ctx->view;
      const cv::Mat full = r.garmentCoverage() > 0.5f;
      const auto intact = pipeline::measureGarment(full, view, type);
      ASSERT_TRUE(intact.measurements.count("hem_circ")) << type << " seed " << seed;
      const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
      const int axis = static_cast<int>(std::lround(view.axisXPx()));
      const cv::Rect box = cv::boundingRect(full);
      const int bottom = box.y + box.height;
      // 0.6 cm wide, 1.5 cm left of the centre front, from the hem 3 cm up.
      cv::Mat notched = full.clone();
      notched(cv::Range(bottom - static_cast<int>(std::lround(3 * s)), bottom),
              cv::Range(axis - static_cast<int>(std::lround(1.5 * s)),
                        axis - static_cast<int>(std::lround(0.9 * s))))
          .setTo(0);
      const auto m = pipeline::measureGarment(notched, view, type);
      ASSERT_TRUE(m.measurements.count("hem_circ")) << type << " seed " << seed;
      EXPECT_NEAR(m.measurements.at("hem_circ"), intact.measurements.at("hem_circ"), 0.5)
          << type << " seed " << seed;
      const double truth = r.truth().at("measurements").at("hem_circ").get<double>();
      EXPECT_NEAR(m.measurements.at("hem_circ"), truth, 3.0) << type << " seed " << seed;
    }
  }
}

// A garment's side is one piece with the rest: where the segmentation cuts a pattern square out
// of the side at the waist (rig H case_013, a green check whose squares at the left edge were
// taken for screen over 9 of the waist band's 15 rows, its side's cloth left 0.4-0.6 cm off the
// run: its waist read 3.3 cm small), the run goes on across the gap, and waist and hip read as
// the intact silhouette's.
TEST(Measure, ASquareCutFromTheSideAtWaistAndHipIsBridged) {
  for (const std::string type : {"dress", "skirt"}) {
    const sim::SceneRenderer r = scene(type, 3, {1224, 1632});
    const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
    const calib::FormView& view = *ctx->view;
    const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
    // The garment 1.5 cm wider each side (a loose one: its side stands off the form's, where no
    // hole inside the form's outline is in question).
    const int wide = static_cast<int>(std::lround(1.5 * s));
    cv::Mat full;
    cv::dilate(r.garmentCoverage() > 0.5f, full,
               cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * wide + 1, 1)));
    const auto intact = pipeline::measureGarment(full, view, type);
    cv::Mat cut = full.clone();
    // Two gaps 0.5 cm wide, 0.5 cm in from the left side, 0.8 cm tall, 0.5 cm apart, about each
    // height (more than half of the ±1 cm band).
    for (const double h : {view.waistCm(), view.hipCm()})
      for (const double from : {-1.0, 0.3}) {
        const int r0 = static_cast<int>(std::lround(view.rowOfHeight(h - from)));
        const int r1 = static_cast<int>(std::lround(view.rowOfHeight(h - from - 0.8)));
        for (int row = r0; row <= r1; ++row) {
          std::vector<cv::Point> on;
          cv::findNonZero(full.row(row), on);
          ASSERT_FALSE(on.empty()) << type << " row " << row;
          const int x = on.front().x;
          cut.row(row)
              .colRange(x + static_cast<int>(std::lround(0.5 * s)),
                        x + static_cast<int>(std::lround(1.0 * s)))
              .setTo(0);
        }
      }
    const auto m = pipeline::measureGarment(cut, view, type);
    for (const std::string name : {"waist_circ", "hip_circ"}) {
      ASSERT_TRUE(intact.measurements.count(name) && m.measurements.count(name)) << type << name;
      EXPECT_NEAR(m.measurements.at(name), intact.measurements.at(name), 0.3)
          << type << " " << name;
    }
  }
}

// A skirt's waistband may sit a little below the form's waist at the centre front (a physical
// rig's skirt dipped 1 cm there): the hem is still followed down from the first covered row, and
// hem and length read as before.
TEST(Measure, AWaistbandDippingBelowTheWaistStillGivesTheHem) {
  const sim::SceneRenderer r = scene("skirt", 3, {720, 960});
  const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
  const calib::FormView& view = *ctx->view;
  const cv::Mat full = r.garmentCoverage() > 0.5f;
  const auto intact = pipeline::measureGarment(full, view, "skirt");
  ASSERT_TRUE(intact.measurements.count("hem_circ"));
  ASSERT_TRUE(intact.measurements.count("skirt_length"));
  const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  const int waistRow = static_cast<int>(std::lround(view.rowOfHeight(view.waistCm())));
  cv::Mat dipped = full.clone();
  dipped(cv::Range(0, waistRow + static_cast<int>(std::lround(1.0 * s))),
         cv::Range(axis - static_cast<int>(2 * s), axis + static_cast<int>(2 * s)))
      .setTo(0);
  const auto m = pipeline::measureGarment(dipped, view, "skirt");
  ASSERT_TRUE(m.measurements.count("hem_circ")) << "hem_circ missing";
  ASSERT_TRUE(m.measurements.count("skirt_length")) << "skirt_length missing";
  EXPECT_NEAR(m.measurements.at("hem_circ"), intact.measurements.at("hem_circ"), 0.3);
  EXPECT_NEAR(m.measurements.at("skirt_length"), intact.measurements.at("skirt_length"), 0.3);
}

// A high-low hem's back shows under its front's hem as a dark band across the middle
// (docs/measurement_model.md, "Hems that are not level"). Darkening a rendered skirt's lowest
// 8 cm to a third of its colour makes that picture: the hem is named, and its length and round
// are read at the band's top, 8 cm higher. A 2 cm band (a level hem's fold and shade read at
// most 0.6 cm on the physical rigs) changes nothing, and without the frame nothing is looked at.
TEST(Measure, AHighLowHemsBackIsReadAtItsFront) {
  const sim::SceneRenderer r = scene("skirt", 3, {720, 960});
  const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
  const calib::FormView& view = *ctx->view;
  const cv::Mat mask = r.garmentCoverage() > 0.5f;
  const cv::Mat frame = r.renderDressed();
  const auto plain = pipeline::measureGarment(mask, view, "skirt");
  const auto looked = pipeline::measureGarment(mask, view, "skirt", frame);
  ASSERT_TRUE(plain.measurements.count("skirt_length"));
  EXPECT_EQ(looked.measurements, plain.measurements);
  EXPECT_EQ(looked.warnings, plain.warnings);
  const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  int hem = mask.rows - 1;
  while (hem > 0 && mask.at<uchar>(hem, axis) == 0)
    --hem;
  const auto banded = [&](double cm) {
    cv::Mat out = frame.clone();
    const int from = hem + 1 - static_cast<int>(std::lround(cm * s));
    for (int y = from; y <= hem; ++y)
      for (int x = 0; x < out.cols; ++x)
        if (mask.at<uchar>(y, x) != 0)
          out.at<cv::Vec3b>(y, x) /= 3;
    return out;
  };
  const auto deep = pipeline::measureGarment(mask, view, "skirt", banded(8.0));
  const auto named = std::find_if(deep.warnings.begin(), deep.warnings.end(), [](const auto& w) {
    return w.rfind("hem: the hem is not level: a dark band", 0) == 0;
  });
  EXPECT_NE(named, deep.warnings.end());
  ASSERT_TRUE(deep.measurements.count("skirt_length"));
  EXPECT_NEAR(deep.measurements.at("skirt_length"), plain.measurements.at("skirt_length") - 8.0,
              0.3);
  ASSERT_TRUE(deep.measurements.count("hem_circ"));
  EXPECT_NE(deep.measurements.at("hem_circ"), plain.measurements.at("hem_circ"));
  const auto shallow = pipeline::measureGarment(mask, view, "skirt", banded(2.0));
  EXPECT_EQ(shallow.measurements, plain.measurements);
  EXPECT_THROW(pipeline::measureGarment(mask, view, "skirt", cv::Mat(10, 10, CV_8UC3)),
               std::invalid_argument);
}

// The garment's top beside the neck: a piece of the head the column grazes (the jaw's edge,
// joined to the silhouette because the garment changed the light on it) lies above the
// shoulder line and does not reach it, so it is not the garment's top.
TEST(Measure, APieceOfTheHeadBesideTheNeckIsNotTheGarmentsTop) {
  const sim::SceneRenderer r = scene("top", 4, {720, 960});
  const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
  const calib::FormView& view = *ctx->view;
  const cv::Mat full = r.garmentCoverage() > 0.5f;
  const auto intact = pipeline::measureGarment(full, view, "top");
  ASSERT_TRUE(intact.measurements.count("garment_length"));
  const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  const int col = axis - static_cast<int>(std::ceil(view.neckHalfWidthPx() + 0.5 * s));
  // 2 cm of "garment" 8-10 cm above the side neck, across the column.
  const int top = static_cast<int>(std::lround(view.rowOfHeight(view.neckSideCm() + 10.0)));
  cv::Mat withJaw = full.clone();
  withJaw(cv::Range(top, top + static_cast<int>(std::lround(2.0 * s))),
          cv::Range(col - static_cast<int>(s), col + static_cast<int>(s)))
      .setTo(255);
  const auto m = pipeline::measureGarment(withJaw, view, "top");
  ASSERT_TRUE(m.measurements.count("garment_length"));
  EXPECT_NEAR(m.measurements.at("garment_length"), intact.measurements.at("garment_length"), 0.3);
}

// Issue 18: the sample size of a captured item (the graded files' sample, the size guide's own
// row) is the chart size of the body the pattern was drafted for, the form's. On the bundled
// form (bust 97.4, waist 80.3, hip 104.1 in its sidecar) that is 88 for every garment; on the
// generated korean_women_55 form it is 55: items are not all 88. The expected size is worked
// out here from the form's sidecar file and the chart's rows by hand.
TEST(WorkFrame, SampleSizeIsTheChartSizeOfTheFormsBody) {
  const drafts::SizeChart& chart = drafts::sizeChart(pipeline::kDefaultSizeChart);
  auto nearestBySidecar = [&](const std::string& path) {
    std::ifstream in(path);
    const auto m = nlohmann::json::parse(in).at("measurements");
    std::string best;
    double bestSq = 1e300;
    for (std::size_t i = 0; i < chart.sizes.size(); ++i) {
      double sq = 0;
      for (const char* n : {"bust_circ", "waist_circ", "hip_circ"}) {
        const double d = m.at(n).get<double>() - chart.bodies[i].get(n);
        sq += d * d;
      }
      if (sq < bestSq) {
        bestSq = sq;
        best = chart.sizes[i];
      }
    }
    return best;
  };
  const std::string narrowPath = std::string(GARMCAP_TEST_DATA_DIR) + "/forms/korean_women_55.json";
  const calib::FormModel narrow = calib::FormModel::load(narrowPath);
  std::set<std::string> seen;
  struct Case {
    const calib::FormModel* model;
    std::string path;
    std::string type;  // a top on the bundled form, a skirt on the other
  };
  for (const Case& c : {Case{&form(), kFormPath, "top"}, Case{&narrow, narrowPath, "skirt"}}) {
    const std::string expected = nearestBySidecar(c.path);
    sim::RandomSceneOptions o;
    o.size = {600, 800};
    o.hardFraction = 0;
    o.type = c.type;
    const sim::SceneRenderer r(*c.model, sim::randomScene(*c.model, c.path, 5, o));
    const auto res =
        pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(), measureOnly(2.0));
    ASSERT_FALSE(res.pattern.panels.empty()) << c.path << " " << c.type;
    const auto size = dsw::sampleSizeOf(res.pattern, chart);
    ASSERT_TRUE(size) << c.path << " " << c.type;
    EXPECT_EQ(chart.sizes[*size], expected) << c.path << " " << c.type;
    seen.insert(chart.sizes[*size]);
  }
  EXPECT_EQ(seen, (std::set<std::string>{"55", "88"}));
}

// The bust from its sides' floor: a thin fold of cloth hanging out at each side just below the
// armhole (a sleeveless cut's underarm, a sleeve's underarm) adds width and little round, so it
// must not move the bust by much (the side is then read on rows further down, 1.35 cm apart on
// seed 4). 1.5 cm beyond the garment's side from 0.5 cm above the bust to 2 cm below it read the
// bust about 9 cm large when the bust was the median of its own rows.
TEST(Measure, AFoldBesideTheBustDoesNotWidenIt) {
  int checked = 0;
  for (const unsigned seed : {4u, 6u}) {
    const sim::SceneRenderer r = scene("top", seed, {720, 960});
    const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
    const calib::FormView& view = *ctx->view;
    const cv::Mat full = r.garmentCoverage() > 0.5f;
    const auto intact = pipeline::measureGarment(full, view, "top");
    if (!intact.measurements.count("bust_circ"))
      continue;  // sleeves hide this top's sides
    const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
    const int top = static_cast<int>(std::lround(view.rowOfHeight(view.bustCm() + 0.5)));
    const int bottom = static_cast<int>(std::lround(view.rowOfHeight(view.bustCm() - 2.0)));
    const int axis = static_cast<int>(std::lround(view.axisXPx()));
    const int fin = static_cast<int>(std::lround(1.5 * s));
    cv::Mat folded = full.clone();
    for (int row = top; row <= bottom; ++row) {
      const uchar* m = full.ptr(row);
      int l = axis, rr = axis;
      while (l > 0 && m[l - 1])
        --l;
      while (rr < full.cols - 1 && m[rr + 1])
        ++rr;
      folded(cv::Range(row, row + 1), cv::Range(std::max(0, l - fin), l)).setTo(255);
      folded(cv::Range(row, row + 1), cv::Range(rr + 1, std::min(full.cols, rr + 1 + fin)))
          .setTo(255);
    }
    const auto m = pipeline::measureGarment(folded, view, "top");
    ASSERT_TRUE(m.measurements.count("bust_circ")) << "seed " << seed;
    ++checked;
    EXPECT_NEAR(m.measurements.at("bust_circ"), intact.measurements.at("bust_circ"), 1.5)
        << "seed " << seed;
  }
  EXPECT_EQ(checked, 2) << "a top's sides were hidden: the test checked less than it says";
}

// A pants leg's hem with the garment's shadow on the shin below it: a tail under one leg, its
// inner edge notched as on a physical rig's slim pants (90 % of the leg's width at the hem,
// narrowing to 65 % over 2 cm, so the leg's hem rule keeps it). Both openings are read above
// the higher of the two hems, so the tail is not read as the leg (the old reading, 1.25 cm above
// the tail's bottom, was across the notch).
TEST(Measure, AShadowTailUnderOneLegDoesNotNarrowItsOpening) {
  int checked = 0;
  for (const unsigned seed : {1u, 2u}) {
    const sim::SceneRenderer r = scene("pants", seed, {720, 960});
    const auto ctx = pipeline::buildCaptureContext(r.calibration(), pipeline::kDefaultSizeChart);
    const calib::FormView& view = *ctx->view;
    const cv::Mat full = r.garmentCoverage() > 0.5f;
    const auto intact = pipeline::measureGarment(full, view, "pants");
    ASSERT_TRUE(intact.measurements.count("leg_opening_circ")) << "seed " << seed;
    const double s = r.calibration().at("pose").at("px_per_cm").get<double>();
    const int axis = static_cast<int>(std::lround(view.axisXPx()));
    // The right leg's hem: the lowest row with garment right of the axis.
    int hem = -1;
    for (int row = full.rows - 1; row >= 0 && hem < 0; --row)
      for (int x = axis + 1; x < full.cols; ++x)
        if (full.at<uchar>(row, x)) {
          hem = row;
          break;
        }
    ASSERT_GT(hem, 0) << "seed " << seed;
    int l = -1, rr = -1;
    for (int x = axis + 1; x < full.cols; ++x)
      if (full.at<uchar>(hem, x)) {
        l = l < 0 ? x : l;
        rr = x;
      }
    ASSERT_GT(rr - l, 10) << "seed " << seed;
    const int rows = static_cast<int>(std::lround(2.0 * s));
    cv::Mat tailed = full.clone();
    for (int k = 1; k <= rows && hem + k < full.rows; ++k) {
      const double share = 0.9 - 0.25 * k / rows;
      const int from = rr - static_cast<int>(std::lround(share * (rr - l)));
      tailed(cv::Range(hem + k, hem + k + 1), cv::Range(from, rr + 1)).setTo(255);
    }
    const auto m = pipeline::measureGarment(tailed, view, "pants");
    ASSERT_TRUE(m.measurements.count("leg_opening_circ")) << "seed " << seed;
    ++checked;
    EXPECT_NEAR(m.measurements.at("leg_opening_circ"), intact.measurements.at("leg_opening_circ"),
                0.5)
        << "seed " << seed;
  }
  EXPECT_EQ(checked, 2);
}
