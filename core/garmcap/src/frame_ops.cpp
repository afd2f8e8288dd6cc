#include "frame_ops.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "garmcap/calib/errors.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {
namespace {

using Reason = CaptureError::Reason;

// The work frames' denoising blur, in work-frame px.
constexpr double kDenoiseSigmaPx = 0.7;

}  // namespace

std::string fmt1(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

cv::Mat rotateAbout(const cv::Mat& img, const Eigen::Vector2d& centre, double rollRad, int interp) {
  // The pose rotates the world counter-clockwise on screen by roll; undo it.
  const cv::Mat m = cv::getRotationMatrix2D(
      cv::Point2f(static_cast<float>(centre.x()), static_cast<float>(centre.y())),
      -rollRad * 180.0 / M_PI, 1.0);
  cv::Mat out;
  cv::warpAffine(img, out, m, img.size(), interp, cv::BORDER_REPLICATE);
  return out;
}

calib::KeyResult keyFrame(const cv::Mat& bgr, const std::string& what) {
  try {
    return calib::keyGreenScreen(bgr, what);
  } catch (const calib::CalibError& e) {
    switch (e.kind()) {
      case calib::CalibErrorKind::kFormCutOff:
        throw CaptureError(
            Reason::kOffForm,
            std::string("the garment or form reaches the edge of the ") + what + ": " + e.what());
      case calib::CalibErrorKind::kNoFormInFrame:
        throw CaptureError(Reason::kBadInput,
                           std::string("nothing stands in front of the green screen in the ") +
                               what + ": " + e.what());
      default:
        throw CaptureError(Reason::kBadInput, e.what());
    }
  }
}

cv::Mat largestComponent(const cv::Mat& mask) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  int best = 0, bestArea = 0;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) > bestArea) {
      bestArea = stats.at<int>(i, cv::CC_STAT_AREA);
      best = i;
    }
  return bestArea == 0 ? cv::Mat() : cv::Mat(labels == best);
}

// Both work frames get the same light blur before segmentation: GrabCut's colour models and
// contrast term are fitted to pixel values, and sensor noise on a dark or finely shaded garment
// spreads its model over the form's colours. Edges move by no more than the blur.
cv::Mat denoised(const cv::Mat& bgr) {
  cv::Mat out;
  cv::GaussianBlur(bgr, out, cv::Size(3, 3), kDenoiseSigmaPx);
  return out;
}

double noiseThreshold(std::vector<float> values, double k) {
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  const double median = *mid;
  for (float& v : values)
    v = static_cast<float>(std::abs(v - median));
  std::nth_element(values.begin(), mid, values.end());
  return median + k * 1.4826 * *mid;
}

}  // namespace garmcap::pipeline
