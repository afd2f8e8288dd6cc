#pragma once
// Small image operations the capture's stages share (internal to the pipeline).

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/calib/chroma_key.h"

namespace garmcap::pipeline {

/// `v` with one decimal, for sentences shown to staff.
std::string fmt1(double v);

/// `img` rotated about `centre` by -rollRad (the pose rotates the world counter-clockwise on
/// screen by roll; this undoes it), edges replicated.
cv::Mat rotateAbout(const cv::Mat& img, const Eigen::Vector2d& centre, double rollRad, int interp);

/// The green-screen key of `bgr`, its failures as CaptureError naming `what` (the frame).
calib::KeyResult keyFrame(const cv::Mat& bgr, const std::string& what);

/// Whether `mask` (CV_8UC1) is set at (row, col); false outside the image.
inline bool maskCovers(const cv::Mat& mask, int row, int col) {
  return row >= 0 && row < mask.rows && col >= 0 && col < mask.cols &&
         mask.at<std::uint8_t>(row, col) != 0;
}

/// The largest 8-connected piece of a mask; empty when the mask is.
cv::Mat largestComponent(const cv::Mat& mask);

/// The work frames' light blur before segmentation (see the .cpp).
cv::Mat denoised(const cv::Mat& bgr);

/// Robust sigmas above the median a value must lie to be more than noise (noiseThreshold).
inline constexpr double kNoiseSigmas = 6.0;

/// Median + k robust sigmas (1.4826 x the median absolute deviation) of `values`.
double noiseThreshold(std::vector<float> values, double k);

}  // namespace garmcap::pipeline
