// The back shot and the ghost-mannequin front through the whole pipeline, on simulator scenes
// whose answer is known: the same top rendered twice on the form, its front (a 10 cm deep round
// neckline, red) and, as if turned back to front, its back (a 2 cm neckline, blue). Ground truth
// is the renderer's own garment coverage and form silhouette, not the pipeline's masks. Label
// "rig" (renders scenes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

#include "common/bundled_form.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

using namespace garmcap;

namespace {

const cv::Size kSize{864, 1152};

sim::Scene frontScene(const std::string& type = "top", unsigned seed = 3) {
  sim::RandomSceneOptions o;
  o.size = kSize;
  o.hardFraction = 0;
  o.type = type;
  sim::Scene s = sim::randomScene(garmcap::testing::bundledForm(),
                                  garmcap::testing::bundledFormPath(), seed, o);
  s.pose.rollRad = 0;  // the upright frame is the rendered one: truth maps pixel for pixel
  s.shake = {};
  s.garment.neckline = "round";
  s.garment.neckDepthCm = 10;
  s.fabric.kind = sim::FabricKind::kSolid;
  s.fabric.base = {0.15f, 0.15f, 0.65f};  // red (BGR)
  return s;
}

// The same garment turned back to front: the back's neckline, the back's colour.
sim::Scene backScene(sim::Scene s) {
  s.garment.neckDepthCm = 2;
  s.fabric.base = {0.65f, 0.35f, 0.1f};  // blue
  s.seed += 1000;                        // its own sensor noise
  return s;
}

pipeline::CaptureOptions photosOnly() {
  pipeline::CaptureOptions o;
  o.makeTexture = false;
  return o;
}

// The garment's box in the frame, from the cut-out's rectangle: the box grown by
// m = round(0.06 x its longer side) on each side (makeProductImages).
cv::Rect garmentBoxOf(const cv::Rect& cutoutRect) {
  for (int m = 0; 2 * m < std::min(cutoutRect.width, cutoutRect.height); ++m) {
    const int w = cutoutRect.width - 2 * m, h = cutoutRect.height - 2 * m;
    if (std::lround(0.06 * std::max(w, h)) == m)
      return {cutoutRect.x + m, cutoutRect.y + m, w, h};
  }
  return {};
}

pipeline::CaptureError::Reason reasonOf(const cv::Mat& empty, const cv::Mat& front,
                                        const cv::Mat& back, const nlohmann::json& cal,
                                        std::string& message) {
  pipeline::CaptureOptions o = photosOnly();
  o.backFrame = back;
  try {
    pipeline::runCapture(empty, front, cal, o);
  } catch (const pipeline::CaptureError& e) {
    message = e.what();
    return e.reason();
  }
  ADD_FAILURE() << "no error";
  return pipeline::CaptureError::Reason::kBadInput;
}

}  // namespace

TEST(GhostMannequinRig, NeckOpeningFilledWithTheBackAndNothingElseChanges) {
  const auto& form = garmcap::testing::bundledForm();
  const sim::SceneRenderer front(form, frontScene());
  const sim::SceneRenderer back(form, backScene(front.scene()));
  const cv::Mat3b empty = front.renderEmpty(), dressed = front.renderDressed(),
                  backFrame = back.renderDressed();

  const pipeline::CaptureResult plain =
      pipeline::runCapture(empty, dressed, front.calibration(), photosOnly());
  pipeline::CaptureOptions withBack = photosOnly();
  withBack.backFrame = backFrame;
  const pipeline::CaptureResult r =
      pipeline::runCapture(empty, dressed, front.calibration(), withBack);

  // Off is as before: without a back shot nothing of it is made; with one, the front's own photos
  // keep every byte.
  EXPECT_TRUE(plain.backProduct.empty() && plain.ghostProduct.empty() && plain.backShot.is_null());
  ASSERT_FALSE(r.ghostProduct.empty()) << nlohmann::json(r.warnings).dump();
  EXPECT_EQ(cv::norm(plain.product, r.product, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(plain.productPortrait, r.productPortrait, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(plain.cutout, r.cutout, cv::NORM_INF), 0.0);

  // The truth: the form's neck exposed between the neck points (rendered form, no garment), and
  // where the back (mirrored about the form's axis) covers it.
  const calib::FormView& view = front.view();
  const double axis = view.axisXPx(), halfNeck = view.neckHalfWidthPx();
  const double neckRow = view.rowOfHeight(view.neckSideCm());
  const cv::Mat1f covF = front.garmentCoverage(), covB = back.garmentCoverage();
  cv::Mat1b opening = cv::Mat1b::zeros(kSize), fill = cv::Mat1b::zeros(kSize);
  // Rows from the side neck down to the front neckline's depth (below the hem the form shows too).
  const int deepest = static_cast<int>(std::ceil(neckRow + front.scene().garment.neckDepthCm *
                                                               front.scene().pose.pxPerCm)) +
                      1;
  for (int y = static_cast<int>(std::ceil(neckRow)) + 1; y <= deepest; ++y)
    for (int x = 0; x < kSize.width; ++x) {
      if (std::abs(x - axis) >= halfNeck - 1 || covF(y, x) > 0.0f || view.coverage()(y, x) < 0.5f)
        continue;
      opening(y, x) = 255;
      const int mx = static_cast<int>(std::lround(2 * axis - x));
      if (mx >= 0 && mx < kSize.width && covB(y, mx) >= 1.0f)
        fill(y, x) = 255;
    }
  ASSERT_GT(cv::countNonZero(fill), 500);

  // Frame to photo: the square centres the garment's box, no scaling at this size.
  const cv::Rect gb = garmentBoxOf(r.cutoutRect);
  ASSERT_GT(gb.area(), 0);
  const int side = r.ghostProduct.cols;
  ASSERT_EQ(side, static_cast<int>(std::ceil(std::max(gb.width, gb.height) / 0.88)));
  const cv::Point toPhoto = cv::Point((side - gb.width) / 2, (side - gb.height) / 2) - gb.tl();
  const cv::Mat3b ghost = r.ghostProduct, product = r.product;
  // The back's colour as the back photos hold it (edge unmixed and despilled, as the front's):
  // the back cut-out placed in the frame, sampled at the mirrored column 2 axis - x (linear
  // between its two neighbours: the axis falls between pixels).
  ASSERT_FALSE(r.backCutout.empty());
  ASSERT_EQ(r.backCutout.size(), r.backCutoutRect.size());
  cv::Mat3b backColour(kSize, cv::Vec3b(0, 0, 0));
  {
    cv::Mat3b bgr;
    cv::cvtColor(r.backCutout, bgr, cv::COLOR_BGRA2BGR);
    const cv::Rect in = r.backCutoutRect & cv::Rect(cv::Point(0, 0), kSize);
    bgr(in - r.backCutoutRect.tl()).copyTo(backColour(in));
  }
  auto mirroredBack = [&](int x, int y) {
    const double xf = 2 * axis - x;
    const int x0 = static_cast<int>(std::floor(xf));
    const double t = xf - x0;
    cv::Vec3d c;
    for (int k = 0; k < 3; ++k)
      c[k] = (1 - t) * backColour(y, x0)[k] + t * backColour(y, x0 + 1)[k];
    return c;
  };

  // Every pixel of the opening the back covers (2 px clear of its edges: the soft edges of both
  // shots) shows the back's colour at the mirrored place, darkened by 0.8 (within 2 levels of
  // rounding) and blue; none of the opening shows the form's colour.
  cv::Mat1b fillInner, openingInner;
  cv::erode(fill, fillInner, cv::Mat(), cv::Point(-1, -1), 2);
  cv::erode(opening, openingInner, cv::Mat(), cv::Point(-1, -1), 1);
  cv::Mat1b fillNear;
  cv::dilate(fill, fillNear, cv::Mat(), cv::Point(-1, -1), 2);
  int checked = 0, wrong = 0, formLeft = 0, blueOff = 0, notWhite = 0;
  double worst = 0;
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x) {
      if (!openingInner(y, x))
        continue;
      const cv::Vec3b g = ghost(y + toPhoto.y, x + toPhoto.x);
      const cv::Vec3b formPx = empty(y, x);
      double toForm = 0;
      for (int c = 0; c < 3; ++c)
        toForm = std::max(toForm, std::abs(g[c] - static_cast<double>(formPx[c])));
      formLeft += toForm < 20;
      // Above the back's neckline (the back does not reach within 2 px): the white background.
      if (!fillNear(y, x))
        notWhite += g != cv::Vec3b(255, 255, 255);
      if (!fillInner(y, x))
        continue;
      const cv::Vec3d b = mirroredBack(x, y);
      double d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(g[c] - 0.8 * b[c]));
      worst = std::max(worst, d);
      blueOff += !(g[0] > g[2] + 40);  // the back's blue, whatever its edge handling
      wrong += d > 2;
      ++checked;
    }
  std::printf(
      "neck opening: %d px truth, %d px the back covers; checked %d, worst %.0f levels, "
      "%d off by more than 2; form-coloured: %d; not white above the back: %d\n",
      cv::countNonZero(opening), cv::countNonZero(fill), checked, worst, wrong, formLeft, notWhite);
  EXPECT_GT(checked, 300);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(blueOff, 0);
  EXPECT_EQ(formLeft, 0);
  EXPECT_EQ(notWhite, 0);

  // Nothing changes outside the opening and 0.5 cm round it.
  cv::Mat1b allowed;
  const int grow = static_cast<int>(std::ceil(0.5 * front.scene().pose.pxPerCm));
  cv::dilate(opening, allowed,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * grow + 1, 2 * grow + 1)));
  int changedOutside = 0, changedInside = 0;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      if (ghost(y, x) == product(y, x))
        continue;
      const cv::Point f(x - toPhoto.x, y - toPhoto.y);
      const bool in =
          f.x >= 0 && f.y >= 0 && f.x < kSize.width && f.y < kSize.height && allowed(f.y, f.x);
      (in ? changedInside : changedOutside) += 1;
    }
  EXPECT_EQ(changedOutside, 0);
  EXPECT_GE(changedInside, checked);

  // The back photos: the back's colour, as the front photos are made.
  ASSERT_FALSE(r.backProduct.empty());
  ASSERT_FALSE(r.backCutout.empty());
  EXPECT_NEAR(static_cast<double>(r.backProductPortrait.cols) / r.backProductPortrait.rows, 0.8,
              0.01);
  const cv::Vec3b centre = cv::Mat3b(r.backProduct)(r.backProduct.rows / 2, r.backProduct.cols / 2);
  EXPECT_GT(centre[0], centre[2] + 40) << "the back photo is not of the blue back";
  std::printf("back shot: %s\n", r.backShot.dump().c_str());
  EXPECT_NEAR(r.backShot.at("area_ratio").get<double>(), 1.0, 0.05);
}

TEST(GhostMannequinRig, BadBackShotsAreRefusedByName) {
  const auto& form = garmcap::testing::bundledForm();
  const sim::SceneRenderer front(form, frontScene());
  const cv::Mat3b empty = front.renderEmpty(), dressed = front.renderDressed();
  std::string message;

  // No garment: the bare form again.
  EXPECT_EQ(reasonOf(empty, dressed, empty, front.calibration(), message),
            pipeline::CaptureError::Reason::kNoGarment);
  EXPECT_EQ(message.rfind("the back shot", 0), 0u) << message;

  // The camera moved between the shots: 40 px down (over 1 cm at this scale).
  const sim::SceneRenderer back(form, backScene(front.scene()));
  cv::Mat moved;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 0, 0, 1, 40);
  cv::warpAffine(back.renderDressed(), moved, shift, kSize, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  EXPECT_EQ(reasonOf(empty, dressed, moved, front.calibration(), message),
            pipeline::CaptureError::Reason::kCameraMoved);
  EXPECT_EQ(message.rfind("the back shot", 0), 0u) << message;

  // Another garment: a dress on the same form, rendered in the same session.
  sim::Scene other = frontScene("dress", 5);
  other.pose = front.scene().pose;
  other.lighting = front.scene().lighting;
  const sim::SceneRenderer dress(form, other);
  EXPECT_EQ(reasonOf(empty, dressed, dress.renderDressed(), front.calibration(), message),
            pipeline::CaptureError::Reason::kOtherGarment);
  EXPECT_NE(message.find("same garment"), std::string::npos) << message;
  std::printf("%s\n", message.c_str());
}
