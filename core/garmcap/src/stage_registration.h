#pragma once
// Stage 1-2 of a capture: the dressed frame undistorted, de-rolled and registered onto the bare
// one, and keyed (internal to the pipeline).

#include <future>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "bare_frame.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/pipeline/capture_context.h"

namespace garmcap::pipeline {

struct RegisteredFrame {
  cv::Mat work;          // the dressed work frame: upright, registered, denoised
  calib::KeyResult key;  // its green-screen key
  // The full dressed frame, undistorted, upright and registered (made beside the later stages).
  std::future<cv::Mat> full;
};

/// Registers `dressedRaw` (the calibration's frame size) onto `bare`. Throws CaptureError
/// kCameraMoved when the camera or form moved beyond what re-registration absorbs; a smaller
/// shift is re-registered and said in `warnings`.
RegisteredFrame registerDressedFrame(const cv::Mat& dressedRaw, const CaptureContext& ctx,
                                     const BareFrame& bare, const WorkGeometry& g,
                                     std::vector<std::string>& warnings);

}  // namespace garmcap::pipeline
