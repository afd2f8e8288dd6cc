#pragma once
// Product photos from a garment mask: the garment cut out with a soft alpha edge (form and
// background removed, the "ghost mannequin" look), centred and cropped, on white and on
// transparent. Colours stay as photographed.

#include <opencv2/core.hpp>

namespace garmcap::pipeline {

struct ProductImageOptions {
  int sizePx = 1600;             // edge of the square product image (capped by the garment's size
                                 // in the frame: never upscaled beyond the camera's detail)
  double marginFraction = 0.06;  // empty border around the garment, per side
  double featherPx = 1.5;        // alpha ramp half-width at full resolution
};

/// BGRA cut-out of the whole frame: colour from `bgr`, alpha from `mask` (CV_8U, non-zero =
/// garment) with a feathered edge. Throws std::invalid_argument on mismatched inputs.
cv::Mat makeCutout(const cv::Mat& bgr, const cv::Mat& mask, double featherPx = 1.5);

struct ProductImages {
  cv::Mat onWhite;      // BGR, square
  cv::Mat transparent;  // BGRA, square
};

/// Crops the cut-out to the garment, centres it in a square with a margin and scales it to
/// `sizePx` (downscaling only). Throws std::invalid_argument when the mask is empty.
ProductImages makeProductImages(const cv::Mat& bgr, const cv::Mat& mask,
                                const ProductImageOptions& options = {});

}  // namespace garmcap::pipeline
