#pragma once
// A dark band inside a skirt's outline just above its lowest edge (internal): the inside of a
// high-low hem's back, seen under its front's hem (docs/measurement_model.md, "Hems that are not
// level").

#include <opencv2/core.hpp>

namespace garmcap::pipeline {

/// How deep (cm) a band darker than kHemBandShare of the skirt above it lies across the middle of
/// the garment just above its lowest edge at the centre, `hemCentre` (column, the row under the
/// centre's last covered row), in `frameBgr` (CV_8UC3) under `garment` (CV_8UC1, the same size).
/// The skirt's own lightness is the median over its middle 5-15 cm above that edge. 0: none, or
/// the centre is not a skirt's hem.
double darkBandAboveHemCm(const cv::Mat& frameBgr, const cv::Mat& garment, cv::Point2d hemCentre,
                          double pxPerCm);

}  // namespace garmcap::pipeline
