#pragma once
// Stage 8 of a capture: the images, from the garment's part of the full frame only: the review
// overlay, the product photos and the fabric's texture (internal).

#include <opencv2/core.hpp>

#include "bare_frame.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/garment_measurer.h"
#include "stage_timer.h"

namespace garmcap::pipeline {

struct CaptureImagesInput {
  const cv::Mat& dressedFull;             // the full dressed frame, upright and registered
  const cv::Mat& garment;                 // the garment's mask on it
  const GarmentMeasurement& measurement;  // its landmarks, for the overlay
  const BareFrame& bare;                  // what the form looked like (the photos' background)
  const cv::Vec3b& screenBgr;             // the screen's colour in the dressed frame
};

/// Sets `result`'s silhouette, overlay, and as `options` ask the product photos and the texture
/// (with the fabric attribute); ends the timer's "images" and "texture" stages.
void makeCaptureImages(const CaptureContext& ctx, const CaptureImagesInput& in,
                       const CaptureOptions& options, StageTimer& timer, CaptureResult& result);

}  // namespace garmcap::pipeline
