#pragma once
// Synthetic bare-form frames for the calibration tests: the form's anti-aliased silhouette
// (calib's projection API) in a skin or grey tone with soft shading, on an unevenly lit green
// screen with sensor noise. The truth is the pose it was drawn with.

#include <cmath>
#include <opencv2/core.hpp>
#include <random>

#include "garmcap/calib/projection.h"

namespace garmcap::calib::test {

struct SceneStyle {
  cv::Vec3f formBgr{150, 170, 205};  // skin-like; grey is {150, 150, 150}
  cv::Vec3f screenBgr{60, 175, 50};
  double unevenness = 0.35;  // relative brightness change across the screen
  double noiseSigma = 3.0;   // grey levels
  unsigned seed = 1;
};

inline cv::Mat3b makeScene(const TriMesh& mesh, const FormPose& pose, cv::Size size,
                           const SceneStyle& style = {}) {
  const cv::Mat1f cov = renderCoverage(mesh, pose, size, 4);
  cv::Mat3b out(size);
  std::mt19937 rng(style.seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(style.noiseSigma));
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const double u = static_cast<double>(x) / size.width,
                   v = static_cast<double>(y) / size.height;
      // A light from the upper left plus a vignette: the screen is far from even.
      const double light = 1.0 - style.unevenness * (0.6 * u + 0.4 * v) -
                           0.15 * ((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5));
      const double shade = 0.85 + 0.15 * std::sin(3.0 * u + 2.0 * v);
      const float a = cov(y, x);
      cv::Vec3b& p = out(y, x);
      for (int c = 0; c < 3; ++c) {
        const double bg = style.screenBgr[c] * light;
        const double fg = style.formBgr[c] * shade;
        p[c] = cv::saturate_cast<uchar>(a * fg + (1 - a) * bg + noise(rng));
      }
    }
  }
  return out;
}

}  // namespace garmcap::calib::test
