#pragma once
// A dark band inside a skirt's outline just above its lowest edge (internal): the inside of a
// high-low hem's back, seen under its front's hem (docs/measurement_model.md, "Hems that are not
// level").

#include <opencv2/core.hpp>
#include <optional>

namespace garmcap::pipeline {

struct HemBand {
  double depthCm = 0;  // how deep the band's dark rows are
  double topRow = 0;   // the upper edge of its highest dark row: the front's hem edge
};

/// The band darker than kHemBandShare of the skirt above it that lies across the middle of the
/// garment just above its lowest edge at the centre, `hemCentre` (column, the row under the
/// centre's last covered row), in `frameBgr` (CV_8UC3) under `garment` (CV_8UC1, the same size).
/// The skirt's own lightness is read from 5 cm above that edge up to `highestRow` (the form's
/// hip). nullopt: none, or the centre is not a skirt's hem.
std::optional<HemBand> darkBandAboveHem(const cv::Mat& frameBgr, const cv::Mat& garment,
                                        cv::Point2d hemCentre, double highestRow, double pxPerCm);

}  // namespace garmcap::pipeline
