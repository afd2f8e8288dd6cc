#include "stage_registration.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "frame_ops.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {
namespace {

// Camera or form shifts below this are re-registered; above it the capture is refused.
constexpr double kMaxShiftCm = 1.0;
constexpr double kMinShiftPx = 1.0;

}  // namespace

RegisteredFrame registerDressedFrame(const cv::Mat& dressedRaw, const CaptureContext& ctx,
                                     const BareFrame& bare, const WorkGeometry& g,
                                     std::vector<std::string>& warnings) {
  const calib::FormPose& pose = ctx.calibration.pose;
  const double s = pose.pxPerCm;
  const double ws = g.scale;
  // The dressed frame undistorted with the calibration's camera model, as the bare frame was
  // before registration (and is in prepareBareFrame): both then share the registered geometry,
  // and the form's and the garment's outlines are where the projection puts them.
  const cv::Mat dressedBgr = ctx.undistorter ? ctx.undistorter->apply(dressedRaw) : dressedRaw;
  RegisteredFrame out;
  cv::Mat& dressed = out.work;
  dressed = dressedBgr;
  if (ws < 1.0)
    cv::resize(dressedBgr, dressed, cv::Size(), ws, ws, cv::INTER_AREA);
  // Remove the camera roll so that image rows are form heights (the work frame here; the full
  // frame below, in one warp with any re-registration shift).
  if (std::abs(pose.rollRad) > 1e-6)
    dressed = rotateAbout(dressed, g.centre, pose.rollRad, cv::INTER_LINEAR);
  dressed = denoised(dressed);
  // The key of the frame as it stands runs beside the motion check: a camera that did not move
  // (the usual capture) needs no other, and the two share no data (the warp below writes a new
  // buffer). It is keyed on a worker thread: the key's frame-sized buffers then come from that
  // thread's malloc arena (pipeline_bench measured the later stages ~5 % slower with them on the
  // calling thread's). Its errors surface at get(), after the motion check: a moved camera can
  // also push the form against the frame's edge, and "the camera moved" is the reason staff can
  // act on.
  auto keyed = std::async(std::launch::async,
                          [frame = dressed] { return keyFrame(frame, "dressed frame"); });

  const FrameMotion motion = bare.motion->motionOf(dressed);
  const double shiftPx = motion.largestPx(0.5 * dressed.rows) / ws;  // full-frame px
  if (shiftPx > kMaxShiftCm * s)
    throw CaptureError(CaptureError::Reason::kCameraMoved,
                       "the camera or the form moved by " + fmt1(shiftPx) + " px (" +
                           fmt1(shiftPx / s) +
                           " cm) since the bare-form frame; capture the bare form again");
  const bool reregister = shiftPx > kMinShiftPx;
  if (reregister) {
    const cv::Matx33d back = motion.registration(dressed.size(), 1.0);
    cv::Mat registered;  // not in place: the key above may still be reading `dressed`
    cv::warpAffine(dressed, registered, cv::Mat(back).rowRange(0, 2), dressed.size(),
                   cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    dressed = registered;
    warnings.push_back("re-registered a camera shift of " + fmt1(shiftPx) + " px");
  }
  // The full dressed frame, upright and registered: one warp, and none when neither applies.
  // Everything it reads is captured by value: it runs on after this function returns.
  out.full = std::async(
      std::launch::async, [dressedBgr, pose, reregister, motion, ws, workSize = dressed.size()] {
        if (std::abs(pose.rollRad) <= 1e-6 && !reregister)
          return dressedBgr;
        const cv::Point2f c(static_cast<float>(pose.offsetPx.x()),
                            static_cast<float>(pose.offsetPx.y()));
        const cv::Mat r = cv::getRotationMatrix2D(c, -pose.rollRad * 180.0 / M_PI, 1.0);
        cv::Matx33d m(r.at<double>(0, 0), r.at<double>(0, 1), r.at<double>(0, 2),
                      r.at<double>(1, 0), r.at<double>(1, 1), r.at<double>(1, 2), 0, 0, 1);
        if (reregister)
          m = motion.registration(workSize, 1.0 / ws) * m;
        cv::Mat full;
        cv::warpAffine(dressedBgr, full, cv::Mat(m).rowRange(0, 2), dressedBgr.size(),
                       cv::INTER_LINEAR, cv::BORDER_REPLICATE);
        return full;
      });
  if (reregister) {
    keyed.wait();  // the unregistered frame's key (or its error) is not wanted
    keyed = std::async(std::launch::async,
                       [frame = dressed] { return keyFrame(frame, "dressed frame"); });
  }
  out.key = keyed.get();
  return out;
}

}  // namespace garmcap::pipeline
