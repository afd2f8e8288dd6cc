#pragma once
// The bare-form frame as segmentation uses it, and the work geometry both frames share
// (internal to the pipeline).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "garmcap/calib/chroma_key.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/frame_motion.h"

namespace garmcap::pipeline {

/// Segmentation runs on copies of about `workMegapixels`; only the garment's outline against the
/// screen is placed at full resolution again, where the key is exact to the pixel. At 12 MP this
/// keeps every whole-frame operation on ~1 MP.
struct WorkGeometry {
  double scale = 1;        // work frame px per full frame px (at most 1)
  double pxPerCm = 0;      // work frame px per cm
  Eigen::Vector2d centre;  // the pose's origin in the work frame (the de-rolling centre)
  cv::Size size;           // the work frame's size
  // The motion's bands, where no garment reaches: the head above the neck and the feet (rows of
  // the work frame).
  int topBandEndRow = 0;
  int bottomBandStartRow = 0;
};

WorkGeometry workGeometry(const CaptureContext& ctx, double workMegapixels);

/// The bare-form frame's de-rolled work frame's side of the motion estimate, and its key
/// (PreparedCapture holds one).
struct BareFrame {
  WorkGeometry geometry;  // the work frame it was prepared on
  std::optional<MotionReference> motion;
  calib::KeyResult key;
  // The undistorted bare frame at full resolution, de-rolled as the dressed one is: the product
  // photos cut what still looks as it did here.
  cv::Mat uprightFull;
};

/// `emptyRaw` (the calibration's frame size, 8-bit BGR) undistorted, scaled to the work frame,
/// de-rolled, denoised, keyed and prepared for the motion estimate. Owns its pixels.
BareFrame prepareBareFrame(const cv::Mat& emptyRaw, const CaptureContext& ctx,
                           const WorkGeometry& g);

}  // namespace garmcap::pipeline
