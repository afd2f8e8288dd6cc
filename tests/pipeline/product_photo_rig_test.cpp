// Product photos on rig cases (issue 17): the whole pipeline runs, and its cut-out is held to
// what a shop would see. On scenes rendered by the simulator, against their ground truth: no
// pixel of the exposed form in the cut-out (alpha > 0.5 where the rendered form shows and no
// garment covers it), the edge's CIELAB a* within 2 units of the garment's inside on a skin-tone
// garment, and photos at the frame's resolution, not the work frame's. On the physical rig
// (cloth draped and path-traced by an independent renderer, with real screen spill), the edge
// colour on its light garments. Label "rig".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "common/bundled_form.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/capture/rig.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/product_images.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

using namespace garmcap;
namespace fs = std::filesystem;

namespace {

const std::string& kFormPath = garmcap::testing::bundledFormPath();

sim::Scene drawn(const std::string& type, unsigned seed, cv::Size size) {
  sim::RandomSceneOptions o;
  o.size = size;
  o.hardFraction = 0;
  o.type = type;
  return sim::randomScene(garmcap::testing::bundledForm(), kFormPath, seed, o);
}

pipeline::CaptureOptions photosOnly(double workMegapixels = 2.0) {
  pipeline::CaptureOptions o;
  o.makeTexture = false;
  o.workMegapixels = workMegapixels;
  return o;
}

// The cut-out's alpha (0..255) placed back into the frame.
cv::Mat1b alphaInFrame(const pipeline::CaptureResult& r, cv::Size frame) {
  cv::Mat1b alpha = cv::Mat1b::zeros(frame);
  cv::Mat1b a;
  cv::extractChannel(r.cutout, a, 3);
  EXPECT_EQ(a.size(), r.cutoutRect.size()) << "the cut-out was scaled";
  const cv::Rect in = r.cutoutRect & cv::Rect(cv::Point(0, 0), frame);
  a(in - r.cutoutRect.tl()).copyTo(alpha(in));
  return alpha;
}

// Mean CIELAB a* of the cut-out's opaque pixels in the outline's band (within `edgeCm` of a
// pixel of alpha <= 0.5) and deep inside (farther than `insideCm`). Measured here on the 8-bit
// colours the PNG holds, by OpenCV's float Lab conversion (a* in CIELAB units).
struct EdgeColour {
  double edgeA = 0, insideA = 0;
  int edgeN = 0, insideN = 0;
};

EdgeColour edgeColour(const cv::Mat& cutoutBgra, double pxPerCm, double edgeCm = 0.5,
                      double insideCm = 3.0) {
  cv::Mat bgr, a;
  cv::cvtColor(cutoutBgra, bgr, cv::COLOR_BGRA2BGR);
  cv::extractChannel(cutoutBgra, a, 3);
  cv::Mat1f depth;
  cv::distanceTransform(a > 127, depth, cv::DIST_L2, cv::DIST_MASK_5);
  cv::Mat f, lab;
  bgr.convertTo(f, CV_32F, 1.0 / 255.0);
  cv::cvtColor(f, lab, cv::COLOR_BGR2Lab);
  EdgeColour e;
  for (int y = 0; y < lab.rows; ++y)
    for (int x = 0; x < lab.cols; ++x) {
      const float d = depth(y, x);
      if (d <= 0)
        continue;
      const double av = lab.at<cv::Vec3f>(y, x)[1];
      if (d <= std::max(2.0, edgeCm * pxPerCm)) {
        e.edgeA += av;
        ++e.edgeN;
      } else if (d > insideCm * pxPerCm) {
        e.insideA += av;
        ++e.insideN;
      }
    }
  if (e.edgeN)
    e.edgeA /= e.edgeN;
  if (e.insideN)
    e.insideA /= e.insideN;
  return e;
}

}  // namespace

// The exposed form: where the rendered form covers more than half a pixel and no garment reaches
// within a pixel (the lens blur spreads the garment's edge over about one). The cut-out must not
// hold any of it at alpha above 0.5: crotch, waistband, neckline and armholes included.
TEST(ProductPhotoRig, NoExposedFormInTheCutout) {
  const auto& form = garmcap::testing::bundledForm();
  for (const std::string type : {"pants", "skirt", "top", "dress"}) {
    for (unsigned seed : {3u, 11u}) {
      if (seed == 11 && (type == "skirt" || type == "dress"))
        continue;  // the time budget: two of each where most is left, the crotch and the checks
      const sim::SceneRenderer r(form, drawn(type, seed, {864, 1152}));
      const cv::Mat empty = r.renderEmpty(), dressed = r.renderDressed();
      const pipeline::CaptureResult res =
          pipeline::runCapture(empty, dressed, r.calibration(), photosOnly());
      ASSERT_FALSE(res.cutout.empty());
      const cv::Mat1b alpha = alphaInFrame(res, empty.size());
      cv::Mat1b garmentNear;
      cv::dilate(r.garmentCoverage() > 0.0f, garmentNear, cv::Mat());
      const cv::Mat1b exposed = (r.view().coverage() > 0.5f) & ~garmentNear;
      const int formInCutout = cv::countNonZero((alpha > 127) & exposed);
      const int formInMask = cv::countNonZero(res.silhouette & exposed);
      // The cut must not eat the garment: its pixels a pixel clear of the true outline stay, up to
      // 1 % of them (light gingham squares at a hem over the light form look as the bare frame
      // did and reach the outline: seed 11's top loses 0.9 % there, segmentation 1.3 %).
      cv::Mat1b garmentInner;
      cv::erode(r.garmentCoverage() > 0.5f, garmentInner, cv::Mat());
      const int garmentLost = cv::countNonZero(garmentInner & (alpha <= 127));
      const int garmentArea = cv::countNonZero(garmentInner);
      const int lostInMask = cv::countNonZero(garmentInner & (res.silhouette == 0));
      std::printf(
          "%-5s seed %2u: exposed form at alpha > 0.5: %d px (segmentation mask: %d px); "
          "garment at alpha <= 0.5: %d of %d px (mask: %d)\n",
          type.c_str(), seed, formInCutout, formInMask, garmentLost, garmentArea, lostInMask);
      EXPECT_EQ(formInCutout, 0) << type << " seed " << seed;
      EXPECT_LE(garmentLost, lostInMask + garmentArea / 100) << type << " seed " << seed;
      // GARMCAP_PHOTO_DEBUG=<dir>: the frame with form left (magenta) and garment lost (yellow).
      if (const char* dir = std::getenv("GARMCAP_PHOTO_DEBUG"); dir) {
        cv::Mat3b vis = dressed.clone();
        vis.setTo(cv::Scalar(255, 0, 255), (alpha > 127) & exposed);
        vis.setTo(cv::Scalar(0, 255, 255), garmentInner & (alpha <= 127));
        cv::imwrite(std::string(dir) + "/" + type + std::to_string(seed) + ".png", vis);
        cv::imwrite(std::string(dir) + "/" + type + std::to_string(seed) + "_empty.png", empty);
        cv::imwrite(std::string(dir) + "/" + type + std::to_string(seed) + "_alpha.png", alpha);
      }
    }
  }
}

// A garment close to the form's colour (the form's beige, a little darker): where it meets the
// form nothing but shading tells them apart, and the cut must not take its edge for the form's.
TEST(ProductPhotoRig, FormColouredGarmentKeepsItsOutline) {
  const auto& form = garmcap::testing::bundledForm();
  for (const std::string type : {"skirt", "top"}) {
    sim::Scene scene = drawn(type, 5, {864, 1152});
    scene.fabric.kind = sim::FabricKind::kSolid;
    scene.fabric.base = scene.lighting.formBgr * 0.92f;
    const sim::SceneRenderer r(form, scene);
    pipeline::CaptureResult res;
    try {
      res = pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(), photosOnly());
    } catch (const pipeline::CaptureError& e) {
      GTEST_SKIP() << type << ": segmentation does not find it: " << e.what();
    }
    const cv::Mat1b alpha = alphaInFrame(res, r.scene().size);
    cv::Mat1b garmentInner;
    cv::erode(r.garmentCoverage() > 0.5f, garmentInner, cv::Mat());
    const int lost = cv::countNonZero(garmentInner & (alpha <= 127));
    const int lostInMask = cv::countNonZero(garmentInner & (res.silhouette == 0));
    const int area = cv::countNonZero(garmentInner);
    std::printf("%s (form-coloured): garment at alpha <= 0.5: %d of %d px (mask: %d)\n",
                type.c_str(), lost, area, lostInMask);
    EXPECT_LE(lost, lostInMask + area / 100) << type;
  }
}

// A skin-tone top: green spill tints its outline olive where it meets the screen; after the
// despill the outline's a* is within 2 units of the garment's inside.
TEST(ProductPhotoRig, SkinToneEdgeKeepsTheInsideColour) {
  const auto& form = garmcap::testing::bundledForm();
  for (const std::string type : {"top", "skirt"}) {
    sim::Scene scene = drawn(type, 7, {864, 1152});
    scene.fabric.kind = sim::FabricKind::kSolid;
    scene.fabric.base = cv::Vec3f(0.58f, 0.68f, 0.90f);  // BGR: a light skin tone
    scene.lighting.spillStrength = 0.35;
    scene.pose.rollRad = 0;  // the raw frame is the upright one: the old cut-out below needs it
    const sim::SceneRenderer r(form, scene);
    const cv::Mat dressed = r.renderDressed();
    const pipeline::CaptureResult res =
        pipeline::runCapture(r.renderEmpty(), dressed, r.calibration(), photosOnly());
    const double s = scene.pose.pxPerCm;
    const EdgeColour e = edgeColour(res.cutout, s);
    // For the record, the cut-out as made before issue 17 from the same silhouette: G <= max(R,
    // B) over the mask grown by 2 px, 1.5 px feather.
    cv::Mat3b old = dressed.clone();
    cv::Mat1b spill;
    cv::dilate(res.silhouette, spill, cv::Mat(), cv::Point(-1, -1), 2);
    calib::despill(old, spill);
    const EdgeColour o = edgeColour(pipeline::makeCutout(old, res.silhouette), s);
    std::printf(
        "%s: edge a* %.2f (%d px), inside a* %.2f (%d px), difference %.2f (before: %.2f)\n",
        type.c_str(), e.edgeA, e.edgeN, e.insideA, e.insideN, e.edgeA - e.insideA,
        o.edgeA - o.insideA);
    ASSERT_GT(e.edgeN, 100);
    ASSERT_GT(e.insideN, 1000);
    EXPECT_LE(std::abs(e.edgeA - e.insideA), 2.0) << type;
  }
}

// A 3 MP frame segmented on a 2 MP work frame: the photos are made from the full frame, so the
// square is as large as the garment there plus the margin (the work frame would give 82 % of it).
TEST(ProductPhotoRig, PhotosAtTheFrameResolution) {
  const auto& form = garmcap::testing::bundledForm();
  const sim::SceneRenderer r(form, drawn("dress", 5, {1500, 2000}));
  const pipeline::CaptureResult res =
      pipeline::runCapture(r.renderEmpty(), r.renderDressed(), r.calibration(), photosOnly());
  const cv::Rect truth = cv::boundingRect(r.garmentCoverage() > 0.5f);
  const int expected = static_cast<int>(std::max(truth.width, truth.height) / 0.88);
  std::printf("garment %dx%d px, square %dx%d, 4:5 %dx%d\n", truth.width, truth.height,
              res.product.cols, res.product.rows, res.productPortrait.cols,
              res.productPortrait.rows);
  EXPECT_EQ(res.product.cols, res.product.rows);
  EXPECT_NEAR(res.product.cols, expected, 0.03 * expected);
  EXPECT_NEAR(static_cast<double>(res.productPortrait.cols) / res.productPortrait.rows, 0.8, 0.01);
  EXPECT_GE(res.productPortrait.rows, res.product.rows);
  // The garment is centred: equal white margins left and right, and above and below.
  cv::Mat1b grey;
  cv::cvtColor(res.product, grey, cv::COLOR_BGR2GRAY);
  const cv::Rect box = cv::boundingRect(grey < 250);
  EXPECT_NEAR(box.x, res.product.cols - box.br().x, 0.01 * res.product.cols);
  EXPECT_NEAR(box.y, res.product.rows - box.br().y, 0.01 * res.product.rows);
}

// The physical rig: the edge colour of every case whose truth names a light fabric, with the
// screen's real spill from the path tracer. Cases the pipeline cannot segment are skipped (the
// accuracy test counts them).
TEST(ProductPhotoRig, PhysicalRigLightGarmentEdges) {
  const fs::path rigDir = fs::path(GARMCAP_TEST_DATA_DIR) / "rig_physical";
  ASSERT_TRUE(fs::exists(rigDir / "rig.json"));
  const auto rig = capture::readRig(rigDir);
  int checked = 0;
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    if (c.truth.at("fabric").at("kind") != "light")
      continue;
    pipeline::CaptureResult res;
    try {
      res = pipeline::runCapture(c.empty, c.dressed, c.calibration, photosOnly());
    } catch (const std::exception& e) {
      std::printf("%s: no capture: %s\n", c.id.c_str(), e.what());
      continue;
    }
    const double s = c.calibration.at("pose").at("px_per_cm").get<double>();
    const EdgeColour e = edgeColour(res.cutout, s);
    std::printf("%s %-5s: edge a* %.2f (%d px), inside a* %.2f (%d px), difference %.2f\n",
                c.id.c_str(), res.type.c_str(), e.edgeA, e.edgeN, e.insideA, e.insideN,
                e.edgeA - e.insideA);
    if (e.insideN < 1000)
      continue;
    ++checked;
    EXPECT_LE(std::abs(e.edgeA - e.insideA), 2.0) << c.id;
  }
  EXPECT_GE(checked, 1);
}

namespace {

// The product layer of one frame pair both ways, from the mask the pipeline segments, the crop
// around it (2 cm margin, as the images stage), the bare frame and the screen colour (the empty
// frame's left edge). Returns whether it compared (the pipeline found a garment) and counts the
// mask pixels the layer made transparent (the cut at work).
bool compareLayers(const std::string& what, const cv::Mat3b& empty, const cv::Mat3b& dressed,
                   const nlohmann::json& calibration, int& cutPixels) {
  pipeline::CaptureOptions opt = photosOnly();
  opt.makeProductImages = false;
  pipeline::CaptureResult res;
  try {
    res = pipeline::runCapture(empty, dressed, calibration, opt);
  } catch (const std::exception& e) {
    std::printf("%s: no capture: %s\n", what.c_str(), e.what());
    return false;
  }
  const cv::Mat1b garment = res.silhouette;
  EXPECT_EQ(garment.size(), dressed.size()) << what;
  if (garment.size() != dressed.size())
    return false;
  const double s = calibration.at("pose").at("px_per_cm").get<double>();
  const int m = static_cast<int>(std::ceil(2.0 * s));
  const cv::Rect tight = cv::boundingRect(garment);
  const cv::Rect box =
      cv::Rect(tight.x - m, tight.y - m, tight.width + 2 * m, tight.height + 2 * m) &
      cv::Rect(0, 0, garment.cols, garment.rows);
  const cv::Scalar screen =
      cv::mean(empty(cv::Rect(0, 0, std::max(1, empty.cols / 30), empty.rows)));
  const cv::Vec3b screenBgr(cv::saturate_cast<uchar>(screen[0]),
                            cv::saturate_cast<uchar>(screen[1]),
                            cv::saturate_cast<uchar>(screen[2]));
  pipeline::ProductImageOptions po{.pxPerCm = s};
  po.wholeCropPasses = true;
  const pipeline::ProductLayer whole =
      pipeline::productLayer(dressed(box), garment(box), empty(box), screenBgr, po);
  po.wholeCropPasses = false;
  const pipeline::ProductLayer near =
      pipeline::productLayer(dressed(box), garment(box), empty(box), screenBgr, po);
  const double alphaDiff = cv::norm(whole.alpha, near.alpha, cv::NORM_INF);
  const double colourDiff = cv::norm(whole.colour, near.colour, cv::NORM_INF);
  cutPixels = cv::countNonZero((garment(box) > 0) & (whole.alpha == 0.0f));
  std::printf(
      "%s: crop %dx%d, %.1f px/cm, mask px at alpha 0: %d, max alpha diff %g, max colour "
      "diff %g\n",
      what.c_str(), box.width, box.height, s, cutPixels, alphaDiff, colourDiff);
  EXPECT_EQ(alphaDiff, 0.0) << what;
  EXPECT_EQ(colourDiff, 0.0) << what;
  return true;
}

}  // namespace

// productLayer keeps its form-remains test and the despill's Lab conversions to the pixels near
// the outline (the only ones whose layer they can change); the whole-crop passes they replaced
// stay as an option. Both must give the same layer, alpha and colour bit for bit, on the
// simulator's rigs, the physical rig and one simulated dress at 12 MP (the rigs' frames are
// small: the tiles and the bands then have other proportions).
TEST(ProductPhotoRig, LayerNearTheOutlineEqualsTheWholeCropPasses) {
  int compared = 0, cutSomewhere = 0;
  for (const char* name : {"rig", "rig_physical"}) {
    const fs::path rigDir = fs::path(GARMCAP_TEST_DATA_DIR) / name;
    ASSERT_TRUE(fs::exists(rigDir / "rig.json")) << rigDir;
    const auto rig = capture::readRig(rigDir);
    for (const auto& info : rig.cases) {
      const auto c = capture::loadRigCase(info.dir);
      int cut = 0;
      if (compareLayers(std::string(name) + "/" + c.id, c.empty, c.dressed, c.calibration, cut)) {
        ++compared;
        cutSomewhere += cut > 0;
      }
    }
  }
  EXPECT_GE(compared, 10);
  EXPECT_GE(cutSomewhere, 1);  // else the comparison would not see the cut at all
  const sim::SceneRenderer r(garmcap::testing::bundledForm(), drawn("dress", 5, {3000, 4000}));
  int cut = 0;
  EXPECT_TRUE(compareLayers("simulated dress 3000x4000", r.renderEmpty(), r.renderDressed(),
                            r.calibration(), cut));
}
