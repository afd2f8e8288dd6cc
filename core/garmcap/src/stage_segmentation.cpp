#include "stage_segmentation.h"

#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

#include "frame_ops.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/grabcut_refine.h"
#include "stage_screen_coloured.h"

namespace garmcap::pipeline {
namespace {

// The garment mask at full resolution from the work-frame one. Where the garment meets the screen
// the full frame's own key places the edge (to the pixel); where it meets the form, or inside,
// the work-frame decision is upsampled. Only a band of a few work pixels around the outline is
// keyed again, so this costs a few percent of a full-frame key.
cv::Mat fullResolution(const cv::Mat& dressedFull, const calib::KeyResult& keyW,
                       const cv::Mat& garmentW, const cv::Mat& formW) {
  // Let the garment reach two work pixels further where the bare frame shows the screen: the
  // full frame's key then decides where it ends there (the work cut may stop a pixel short of
  // the screen at mixed edge pixels). Over the form it stays as the work frame cut it.
  cv::Mat grown;
  cv::dilate(garmentW, grown, cv::Mat(), cv::Point(-1, -1), 2);
  const cv::Mat extended = garmentW | (grown & ~formW);
  cv::Mat bandW;
  cv::morphologyEx(garmentW, bandW, cv::MORPH_GRADIENT, cv::Mat());
  cv::dilate(bandW, bandW, cv::Mat(), cv::Point(-1, -1), 2);
  cv::Mat up, band;
  cv::resize(extended, up, dressedFull.size(), 0, 0, cv::INTER_LINEAR);
  cv::resize(bandW, band, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat full;
  cv::resize(garmentW, full, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
  const cv::Mat1b fg = calib::foregroundInRegion(dressedFull, keyW, band);
  // The full frame's key decides only where the work frame's key saw a foreground too: a garment
  // close to the screen's colour was found against the bare frame, and the key would cut it
  // back. There the work decision is upsampled smoothly instead.
  cv::Mat keyed;
  cv::dilate(keyW.mask | formW, keyed, cv::Mat(), cv::Point(-1, -1), 3);
  cv::Mat inBand = (up >= 128) & fg;
  if (cv::countNonZero(bandW & ~keyed) > 0) {
    cv::Mat keyedUp, smooth;
    cv::resize(keyed, keyedUp, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
    cv::resize(garmentW, smooth, dressedFull.size(), 0, 0, cv::INTER_LINEAR);
    inBand = (inBand & keyedUp) | ((smooth >= 128) & ~keyedUp);
  }
  inBand.copyTo(full, band);
  return full;
}

// A garment must be worn by the form: mostly over it and clear of the frame's edges.
void checkWornInFrame(const cv::Mat& garmentW, const cv::Mat& formMask,
                      const calib::Calibration& cal, const WorkGeometry& g) {
  // The frame may cut the form's legs or stand, never the garment: a hem out of view leaves a
  // length that cannot be measured (and a circumference at a hem that is not there).
  const int m = 2;
  const auto touches = [&](cv::Rect strip) { return cv::countNonZero(garmentW(strip)) > 0; };
  const int w = garmentW.cols, h = garmentW.rows;
  if (touches({0, h - m, w, m}))
    throw CaptureError(
        CaptureError::Reason::kOffForm,
        "the garment leaves the frame at its bottom edge" +
            (cal.frameBottomCm ? " (at " + fmt1(*cal.frameBottomCm) + " cm on the form)"
                               : std::string()) +
            ": its hem is out of view, so its length and hem cannot be measured; move the "
            "camera back or lower it so the whole garment is in view");
  for (const auto& [name, strip] : {std::pair<const char*, cv::Rect>{"top", {0, 0, w, m}},
                                    {"left", {0, 0, m, h}},
                                    {"right", {w - m, 0, m, h}}})
    if (touches(strip))
      throw CaptureError(CaptureError::Reason::kOffForm,
                         std::string("the garment is cut off by the frame's ") + name +
                             " edge; move the camera back so the "
                             "whole garment is in view");
  // A form without a crotch may be a torso on a stand: a skirt or dress hangs below its torso
  // over nothing but the pole (a long skirt on a torso form: 22 % over the form). There only the
  // garment above the hip is weighed.
  cv::Mat weighed = garmentW;
  const auto& lm = cal.landmarkHeightsCm;
  if (!lm.count("crotch") && lm.count("hip")) {
    const int hipRow = std::clamp(
        static_cast<int>(std::lround(g.centre.y() - lm.at("hip") * g.pxPerCm)), 0, garmentW.rows);
    weighed = garmentW.clone();
    weighed.rowRange(hipRow, garmentW.rows).setTo(0);
  }
  const double onForm = cv::countNonZero(weighed & formMask) /
                        std::max(1.0, static_cast<double>(cv::countNonZero(weighed)));
  if (onForm < 0.25)
    throw CaptureError(CaptureError::Reason::kOffForm,
                       "the garment hangs off the form (only " +
                           std::to_string(static_cast<int>(onForm * 100)) +
                           "% of it covers the form)");
}

}  // namespace

cv::Mat segmentGarment(const calib::KeyResult& keyD, const GarmentMasks& masks,
                       const calib::Calibration& cal, const WorkGeometry& g) {
  cv::Mat garmentW = grabCutCoarseToFine(keyD.despilled, masks.trimap);
  if (masks.screenChange)
    garmentW = repairScreenColouredGarment(garmentW, masks.foreground, masks.exposed,
                                           *masks.screenChange, g.pxPerCm);
  // Keep the garment's main piece and fill its holes (prints the colour of the form).
  garmentW = largestComponent(garmentW);
  if (garmentW.empty())
    throw CaptureError(CaptureError::Reason::kNoGarment, "no garment found after segmentation");
  {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(garmentW.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    garmentW.setTo(0);
    cv::drawContours(garmentW, contours, -1, cv::Scalar(255), cv::FILLED);
  }
  checkWornInFrame(garmentW, masks.form, cal, g);
  return garmentW;
}

cv::Mat garmentAtFullResolution(const cv::Mat& garmentW, const cv::Mat& dressedFull,
                                const calib::KeyResult& keyD, const GarmentMasks& masks,
                                const WorkGeometry& g) {
  return g.scale >= 1.0 ? garmentW : fullResolution(dressedFull, keyD, garmentW, masks.form);
}

}  // namespace garmcap::pipeline
