#pragma once
// The optional back shot of a capture: the same garment turned back to front on the form, taken by
// the same camera against the same bare-form frame. It gives the back photos and, laid into the
// front photo's neck opening, the ghost-mannequin front photo (internal to the pipeline).

#include <opencv2/core.hpp>

#include "bare_frame.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "stage_images.h"
#include "stage_timer.h"

namespace garmcap::pipeline {

/// Segments `backRaw` as a dressed frame against `bare`, checks it shows the front's garment
/// (`frontGarment`, the front's full-frame mask: outline areas within kBackAreaTolerance), and
/// sets `result`'s back photos, ghost photos and backShot. Throws CaptureError with a message
/// starting "the back shot": the reasons of a dressed frame (kNoGarment, kCameraMoved, kOffForm,
/// kBadInput) and kOtherGarment. Ends the timer's "back" stage.
void makeBackShotImages(const CaptureContext& ctx, const BareFrame& bare, const cv::Mat& backRaw,
                        const cv::Mat& frontGarment, const PhotoLayer& front,
                        const CaptureOptions& options, StageTimer& timer, CaptureResult& result);

}  // namespace garmcap::pipeline
