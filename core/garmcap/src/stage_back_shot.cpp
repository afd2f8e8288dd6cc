#include "stage_back_shot.h"

#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "frame_ops.h"
#include "garmcap/pipeline/ghost_mannequin.h"
#include "garmcap/pipeline/product_images.h"
#include "leg_gap.h"
#include "stage_masks.h"
#include "stage_registration.h"
#include "stage_segmentation.h"

namespace garmcap::pipeline {
namespace {

using Reason = CaptureError::Reason;

// How far from the neck opening the front's soft edge takes the inside behind it: the guided
// filter's ramp (0.12 cm each side of the outline, product_images.cpp) and a pixel more.
constexpr double kGhostRimCm = 0.25;

struct BackGarment {
  cv::Mat full;     // the back frame, upright and registered
  cv::Mat garment;  // its garment mask, full resolution
  cv::Vec3b screenBgr;
};

BackGarment segmentBack(const CaptureContext& ctx, const BareFrame& bare, const cv::Mat& backRaw,
                        std::vector<std::string>& warnings) {
  if (backRaw.empty() || backRaw.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput, "the back shot is empty or not an 8-bit colour image");
  if (backRaw.size() != ctx.calibration.imageSize)
    throw CaptureError(Reason::kBadInput,
                       "the back shot is " + std::to_string(backRaw.cols) + "x" +
                           std::to_string(backRaw.rows) + " but the calibration is for " +
                           std::to_string(ctx.calibration.imageSize.width) + "x" +
                           std::to_string(ctx.calibration.imageSize.height));
  try {
    const WorkGeometry& g = bare.geometry;
    RegisteredFrame back = registerDressedFrame(backRaw, ctx, bare, g, warnings);
    const GarmentMasks masks = garmentMasks(bare.key, back.key, *ctx.view, g, warnings);
    const cv::Mat garmentW = segmentGarment(back.key, masks, ctx.calibration, g);
    BackGarment out;
    out.full = back.full.get();
    out.garment = garmentAtFullResolution(garmentW, out.full, back.key, masks, g);
    carveGapBetweenLegs(out.garment, out.full, *ctx.view, warnings);
    out.screenBgr = back.key.screenBgr;
    return out;
  } catch (const CaptureError& e) {
    throw CaptureError(e.reason(), std::string("the back shot: ") + e.what());
  }
}

}  // namespace

void makeBackShotImages(const CaptureContext& ctx, const BareFrame& bare, const cv::Mat& backRaw,
                        const cv::Mat& frontGarment, const PhotoLayer& front,
                        const CaptureOptions& options, StageTimer& timer, CaptureResult& result) {
  if (front.layer.alpha.empty())
    throw CaptureError(Reason::kBadInput,
                       "the back shot needs the product images (they are turned off)");
  std::vector<std::string> notes;
  const BackGarment back = segmentBack(ctx, bare, backRaw, notes);
  for (const auto& n : notes)
    result.warnings.push_back("back shot: " + n);

  // The same garment turned round covers about the same area of the frame (its back neckline
  // fills the front's neck opening; docs/formats.md gives the tolerance's reasons).
  const double frontArea = cv::countNonZero(frontGarment);
  const double backArea = cv::countNonZero(back.garment);
  const double change = backArea / frontArea - 1.0;
  if (std::abs(change) > kBackAreaTolerance)
    throw CaptureError(Reason::kOtherGarment,
                       "the back shot: its garment covers " + fmt1(100.0 * std::abs(change)) +
                           (change > 0 ? " % more" : " % less") +
                           " of the frame than the front's (at most " +
                           fmt1(100.0 * kBackAreaTolerance) +
                           " % differ for one garment); put the same garment on the form, turned "
                           "back to front, and take the back shot again");

  const double s = ctx.calibration.pose.pxPerCm;
  const ProductImageOptions po = productImageOptions(options, back.full.size(), s);
  const cv::Rect box = photoBox(back.garment, s);
  const ProductLayer backLayer =
      productLayer(back.full(box), back.garment(box), bare.uprightFull(box), back.screenBgr, po);
  const ProductImages bp = makeProductImages(backLayer.colour, backLayer.alpha, po);
  result.backCutout = bp.cutout;
  result.backCutoutRect = bp.cutoutRect + box.tl();
  result.backProduct = bp.square;
  result.backProductPortrait = bp.portrait;

  // The ghost front: the inside of the back, mirrored about the form's axis (both shots are
  // registered onto the same bare frame), in the front's neck opening.
  const double axis = ctx.view->axisXPx();
  const NeckOpening opening = neckOpening(front.layer.alpha >= 0.5f, axis - front.box.x);
  result.backShot = {{"area_ratio", backArea / frontArea}, {"neck_opening_px", 0}};
  if (opening.region.empty()) {
    result.warnings.push_back("no ghost-mannequin photo: " + opening.whyNone);
  } else {
    ProductLayer ghost{front.layer.colour.clone(), front.layer.alpha.clone()};
    const ProductLayer inside = mirroredLayer(backLayer, box, axis, front.box);
    const int rim = static_cast<int>(std::ceil(kGhostRimCm * s));
    const int changed = composeGhostFront(ghost, inside, opening.region, rim);
    const ProductImages gp = makeProductImages(
        ghost.colour, ghost.alpha, productImageOptions(options, frontGarment.size(), s));
    result.ghostProduct = gp.square;
    result.ghostProductPortrait = gp.portrait;
    result.backShot["neck_opening_px"] = cv::countNonZero(opening.region);
    result.backShot["ghost_px"] = changed;
    if (changed == 0)
      result.warnings.push_back(
          "the ghost-mannequin photo is the plain front: the back shot's garment does not reach "
          "into the front's neck opening");
  }
  timer.done("back");
}

}  // namespace garmcap::pipeline
