#include "bare_frame.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "frame_ops.h"

namespace garmcap::pipeline {

WorkGeometry workGeometry(const CaptureContext& ctx, double workMegapixels) {
  const calib::Calibration& cal = ctx.calibration;
  const FormView& view = *ctx.view;
  WorkGeometry g;
  const cv::Size full = cal.imageSize;
  g.scale = std::min(1.0, std::sqrt(workMegapixels * 1e6 / static_cast<double>(full.area())));
  g.pxPerCm = cal.pose.pxPerCm * g.scale;
  g.centre = cal.pose.offsetPx * g.scale;
  // As cv::resize sizes a frame scaled by `scale`.
  g.size = g.scale >= 1.0 ? full
                          : cv::Size(cv::saturate_cast<int>(full.width * g.scale),
                                     cv::saturate_cast<int>(full.height * g.scale));
  g.topBandEndRow = static_cast<int>(view.rowOfHeight(view.neckSideCm() + 2.0) * g.scale);
  // When the frame cuts the form's legs the bottom rows may hold a skirt's hem or a dress: no
  // band there, and the motion is read as a shift only.
  g.bottomBandStartRow = cal.frameBottomCm ? g.size.height : static_cast<int>(g.size.height * 0.85);
  return g;
}

BareFrame prepareBareFrame(const cv::Mat& emptyRaw, const CaptureContext& ctx,
                           const WorkGeometry& g) {
  const double rollRad = ctx.calibration.pose.rollRad;
  const cv::Mat emptyFull = ctx.undistorter ? ctx.undistorter->apply(emptyRaw) : emptyRaw;
  cv::Mat work = emptyFull;
  if (g.scale < 1.0)
    cv::resize(emptyFull, work, cv::Size(), g.scale, g.scale, cv::INTER_AREA);
  if (std::abs(rollRad) > 1e-6)
    work = rotateAbout(work, g.centre, rollRad, cv::INTER_LINEAR);
  work = denoised(work);
  BareFrame bare;
  bare.geometry = g;
  // Its own pixels, never the caller's frame: the prepared frame outlives the call.
  if (std::abs(rollRad) > 1e-6)
    bare.uprightFull = rotateAbout(emptyFull, g.centre / g.scale, rollRad, cv::INTER_LINEAR);
  else
    bare.uprightFull = emptyFull.data == emptyRaw.data ? emptyRaw.clone() : emptyFull;
  bare.motion.emplace(work, g.topBandEndRow, g.bottomBandStartRow);
  bare.key = keyFrame(work, "bare-form frame");
  return bare;
}

}  // namespace garmcap::pipeline
