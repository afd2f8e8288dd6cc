#pragma once
// Stage 5 of a capture: the garment's type and attributes by silhouette against the references
// drawn on this form, and the overrides the legs below the crotch decide (internal).

#include <opencv2/core.hpp>

#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {

/// Sets `result`'s type, attributes, confidence and runner-up (with a warning for each override)
/// from the garment's work-frame mask `garmentW` (what the classifier compares) and its full
/// mask `garment`. Returns the best match's score (IoU).
double classifyGarment(const CaptureContext& ctx, const cv::Mat& garmentW, const cv::Mat& garment,
                       CaptureResult& result);

}  // namespace garmcap::pipeline
