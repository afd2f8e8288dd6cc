#include "stage_images.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "garmcap/pipeline/product_images.h"
#include "garmcap/pipeline/texture.h"

namespace garmcap::pipeline {
namespace {

// Shops zoom product photos of 2048 px and more: from a frame that large, the photos reach it
// (scaled up by 1.5x at most when the garment spans less of the frame).
constexpr int kShopZoomPx = 2048;

// The review overlay: the garment's outline and the landmarks on the dressed work frame (upright,
// registered and lightly denoised). It is a review aid, not a product file: at the work frame's
// size (about 2 MP) it shows the outline to a work pixel, where the full frame's copy and PNG
// cost a 36 MB copy, about 0.35 s of encoding and 20 MB stored per 12 MP capture (1.7 MB now).
// The outline is the full-resolution mask's, scaled down: the cut the measurements and photos
// used.
cv::Mat drawOverlay(const cv::Mat& work, double scale, const cv::Mat& garmentMask,
                    const GarmentMeasurement& m, const calib::Calibration& cal) {
  cv::Mat overlay = work.clone();
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(garmentMask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  // Pixel centres scaled about the pixels' corners, as cv::resize places them.
  const auto scaled = [scale](cv::Point2d p) {
    return cv::Point2d((p.x + 0.5) * scale - 0.5, (p.y + 0.5) * scale - 0.5);
  };
  for (auto& c : contours)
    for (cv::Point& p : c)
      p = scaled(p);
  const int thick = std::max(1, overlay.cols / 600);
  cv::drawContours(overlay, contours, -1, cv::Scalar(0, 255, 255), thick);
  for (const auto& [name, p] : cal.landmarks)
    cv::circle(overlay, scaled(cv::Point2d(p.x(), p.y())), 2 * thick, cv::Scalar(255, 128, 0),
               cv::FILLED);
  for (const auto& lm : m.landmarks) {
    cv::circle(overlay, scaled(lm.px), 3 * thick, cv::Scalar(0, 0, 255), cv::FILLED);
    cv::putText(overlay, lm.name, scaled(lm.px) + cv::Point2d(4 * thick, 0),
                cv::FONT_HERSHEY_SIMPLEX, 0.35 * thick, cv::Scalar(0, 0, 255), thick);
  }
  return overlay;
}

}  // namespace

ProductImageOptions productImageOptions(const CaptureOptions& options, cv::Size frame,
                                        double pxPerCm) {
  return {.maxSidePx = options.productSizePx,
          .minSidePx = std::max(frame.width, frame.height) >= kShopZoomPx
                           ? std::min(kShopZoomPx, options.productSizePx)
                           : 0,
          .marginFraction = 0.06,
          .pxPerCm = pxPerCm,
          .shadow = options.productShadow};
}

cv::Rect photoBox(const cv::Mat& garment, double pxPerCm) {
  const int margin = static_cast<int>(std::ceil(2.0 * pxPerCm));
  const cv::Rect box = cv::boundingRect(garment);
  return cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) &
         cv::Rect(0, 0, garment.cols, garment.rows);
}

PhotoLayer makeCaptureImages(const CaptureContext& ctx, const CaptureImagesInput& in,
                             const CaptureOptions& options, StageTimer& timer,
                             CaptureResult& result) {
  PhotoLayer front;
  const cv::Mat& dressedFull = in.dressedFull;
  const cv::Mat& garment = in.garment;
  const double s = ctx.calibration.pose.pxPerCm;
  result.silhouette = garment;
  result.overlay =
      drawOverlay(in.dressedWork, in.workScale, garment, in.measurement, ctx.calibration);
  if (options.makeProductImages || options.makeTexture) {
    const cv::Rect box = photoBox(garment, s);
    const cv::Mat3b crop = dressedFull(box);
    const cv::Mat1b maskCrop = garment(box);
    // The fabric's texture reads the same crop as the product photos and nothing they write, so
    // it is extracted beside them.
    std::future<TextureResult> texture;
    if (options.makeTexture)
      texture = std::async(std::launch::async, [crop, maskCrop] {
        cv::Mat3b despilled = crop.clone();
        cv::Mat1b spill;
        cv::dilate(maskCrop, spill, cv::Mat(), cv::Point(-1, -1), 2);
        calib::despill(despilled, spill);
        return extractTexture(despilled, maskCrop);
      });
    if (options.makeProductImages) {
      const ProductImageOptions po = productImageOptions(options, dressedFull.size(), s);
      front.layer = productLayer(crop, maskCrop, in.bare.uprightFull(box), in.screenBgr, po);
      front.box = box;
      const ProductImages p = makeProductImages(front.layer.colour, front.layer.alpha, po);
      result.cutout = p.cutout;
      result.cutoutRect = p.cutoutRect + box.tl();
      result.product = p.square;
      result.productPortrait = p.portrait;
    }
    timer.done("images");
    if (texture.valid()) {
      const TextureResult t = texture.get();  // "texture" times only what is left of it
      result.texture = t.tile;
      result.attributes["fabric"] = drafts::fabricKindName(t.kind);
      timer.done("texture");
    }
  } else {
    timer.done("images");
  }
  return front;
}

}  // namespace garmcap::pipeline
