#pragma once
// The colours a shop lists for a garment: its pixels named by the nearest colour of a small
// palette of the names shops and Google Merchant Center use ("Navy", "Beige", ...), the
// dominant ones first, and whether the garment is a print (dots, stripes, checks, florals: a
// good share of it departs from the colour of the cloth around it) rather than a plain colour
// with folds and shading, or a few large colour blocks.
//
// Pure function of an image and a mask; no I/O. Thread-safe.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::daemon {

struct NamedColour {
  std::string name;   // palette name, e.g. "Navy"
  double share = 0;   // fraction of the garment's pixels (blends at colour edges left out)
  cv::Vec3b meanBgr;  // mean colour of those pixels
};

struct GarmentColours {
  std::vector<NamedColour> colours;  // dominant first; each at least kMinShare of the garment
  bool printed = false;
  /// Share of the garment's inside (about 1.3 cm in from the outline) whose colour is more than
  /// 12 ΔE (CIE76) from the median colour of the 4-5 cm around it; a print above 0.05.
  double printShare = 0;
  /// "Navy" or "Navy/White" (up to three names), the form Merchant's `color` takes.
  std::string label() const;
};

/// Palette names, in no particular order (for documentation and the UI's colour picker).
const std::vector<std::string>& colourPaletteNames();

/// The typical colour (BGR) of a palette name; std::invalid_argument for a name not in it.
cv::Vec3b paletteColourBgr(const std::string& name);

/// `bgr`: CV_8UC3 frame; `mask`: CV_8UC1 of the same size, non-zero on the garment. The edge
/// (3 px) is left out, where the garment's colour mixes with what is behind it. Throws
/// std::invalid_argument on mismatched inputs or a mask with fewer than 100 garment pixels.
GarmentColours garmentColours(const cv::Mat& bgr, const cv::Mat& mask);

/// The colours of a capture's garment as the station names them: from the cut-out's opaque
/// pixels (alpha > 200: the garment alone, despilled), else from `dressedBgr` under the
/// silhouette; nullopt when the capture has neither. Throws as garmentColours does.
std::optional<GarmentColours> captureColours(const pipeline::CaptureResult& capture,
                                             const cv::Mat& dressedBgr);

}  // namespace garmcap::daemon
