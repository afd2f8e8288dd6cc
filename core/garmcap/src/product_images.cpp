#include "garmcap/pipeline/product_images.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace garmcap::pipeline {

cv::Mat makeCutout(const cv::Mat& bgr, const cv::Mat& mask, double featherPx) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("cutout: frame must be an 8-bit BGR image");
  if (mask.size() != bgr.size() || mask.type() != CV_8UC1)
    throw std::invalid_argument("cutout: mask must be CV_8UC1 of the frame's size");
  // A hard mask edge shows stair steps on the white background; a short ramp centred on the
  // boundary hides them without eating into the garment.
  cv::Mat alpha;
  cv::threshold(mask, alpha, 0, 255, cv::THRESH_BINARY);
  if (featherPx > 0) {
    const int k = 2 * static_cast<int>(std::ceil(2 * featherPx)) + 1;
    cv::GaussianBlur(alpha, alpha, cv::Size(k, k), featherPx);
  }
  cv::Mat bgra;
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  cv::Mat channels[4];
  cv::split(bgra, channels);
  channels[3] = alpha;
  cv::merge(channels, 4, bgra);
  return bgra;
}

ProductImages makeProductImages(const cv::Mat& bgr, const cv::Mat& mask,
                                const ProductImageOptions& options) {
  const cv::Mat cutout = makeCutout(bgr, mask, options.featherPx);
  const cv::Rect box = cv::boundingRect(mask);
  if (box.area() == 0)
    throw std::invalid_argument("product image: the garment mask is empty");

  // Square canvas around the garment with the margin, in frame pixels.
  const int side = static_cast<int>(
      std::ceil(std::max(box.width, box.height) / (1.0 - 2.0 * options.marginFraction)));
  cv::Mat canvas(side, side, CV_8UC4, cv::Scalar(0, 0, 0, 0));
  const cv::Point offset((side - box.width) / 2, (side - box.height) / 2);
  cutout(box).copyTo(canvas(cv::Rect(offset, box.size())));

  const int target = std::min(options.sizePx, side);
  cv::Mat transparent;
  if (target < side)
    cv::resize(canvas, transparent, cv::Size(target, target), 0, 0, cv::INTER_AREA);
  else
    transparent = canvas;

  // Composite on white with the alpha channel, in 8 bits: a float copy of a 1600x1600 image
  // costs more than the whole composite.
  ProductImages out;
  out.onWhite.create(transparent.size(), CV_8UC3);
  for (int y = 0; y < transparent.rows; ++y) {
    const cv::Vec4b* src = transparent.ptr<cv::Vec4b>(y);
    cv::Vec3b* dst = out.onWhite.ptr<cv::Vec3b>(y);
    for (int x = 0; x < transparent.cols; ++x) {
      const int a = src[x][3];
      for (int c = 0; c < 3; ++c)
        dst[x][c] = static_cast<uchar>((src[x][c] * a + 255 * (255 - a) + 127) / 255);
    }
  }
  out.transparent = transparent;
  return out;
}

}  // namespace garmcap::pipeline
