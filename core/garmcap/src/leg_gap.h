#pragma once
// The gap between a pair of pants' legs where the legs touch (internal): the dark slit the
// segmentation takes for garment (docs/measurement_model.md, "Legs that touch").

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/pipeline/capture_context.h"

namespace garmcap::pipeline {

/// Removes from `garment` (CV_8UC1, the frame's size) the dark slit between two touching legs in
/// `dressedBgr`, when one runs down from the form's crotch; returns its length in cm (0: none).
double carveGapBetweenLegs(cv::Mat& garment, const cv::Mat& dressedBgr, const FormView& view,
                           std::vector<std::string>& warnings);

}  // namespace garmcap::pipeline
