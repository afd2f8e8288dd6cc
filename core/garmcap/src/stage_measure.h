#pragma once
// Stage 6 of a capture: the garment's measurements, their uncertainty and the shop's
// corrections, and the attributes measurements decide better than shape does (internal).

#include <opencv2/core.hpp>

#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/garment_measurer.h"

namespace garmcap::pipeline {

/// Measures the full-resolution garment mask `garment` as `result.type` and sets `result`'s
/// measurements, uncertainties, corrections (from `options.corrections`), sleeve and skirt
/// attributes and warnings; `frame` is the dressed frame the mask was cut from (a skirt's hem
/// is looked at in it: hem_band.h). Returns the raw measurement (its landmarks draw the overlay).
GarmentMeasurement measureCapturedGarment(const CaptureContext& ctx, const cv::Mat& frame,
                                          const cv::Mat& garment, const CaptureOptions& options,
                                          CaptureResult& result);

}  // namespace garmcap::pipeline
