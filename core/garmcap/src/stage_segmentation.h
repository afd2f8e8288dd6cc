#pragma once
// Stage 4 of a capture: GrabCut refines the trimap to the garment, which must be worn by the form
// and clear of the frame's edges; its outline against the screen is placed again at full
// resolution (internal to the pipeline).

#include <opencv2/core.hpp>

#include "bare_frame.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/calib/registration.h"
#include "stage_masks.h"

namespace garmcap::pipeline {

/// The garment's mask on the work frame (one piece, holes filled), segmented from the dressed
/// work frame's key `keyD` and `masks`. Throws CaptureError kNoGarment when nothing is left,
/// kOffForm when the garment hangs off the form or leaves the frame.
cv::Mat segmentGarment(const calib::KeyResult& keyD, const GarmentMasks& masks,
                       const calib::Calibration& cal, const WorkGeometry& g);

/// The garment mask `garmentW` at the resolution of `dressedFull` (the full dressed frame,
/// upright and registered): where the garment meets the screen the full frame's own key places
/// the edge; elsewhere the work-frame decision is upsampled.
cv::Mat garmentAtFullResolution(const cv::Mat& garmentW, const cv::Mat& dressedFull,
                                const calib::KeyResult& keyD, const GarmentMasks& masks,
                                const WorkGeometry& g);

}  // namespace garmcap::pipeline
