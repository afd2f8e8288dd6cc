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

  // Composite on white with the alpha channel.
  cv::Mat colour, alpha;
  cv::cvtColor(transparent, colour, cv::COLOR_BGRA2BGR);
  cv::extractChannel(transparent, alpha, 3);
  cv::Mat colourF, alphaF;
  colour.convertTo(colourF, CV_32FC3, 1.0 / 255);
  alpha.convertTo(alphaF, CV_32F, 1.0 / 255);
  cv::Mat alpha3;
  cv::merge(std::vector<cv::Mat>{alphaF, alphaF, alphaF}, alpha3);
  cv::Mat white(colourF.size(), CV_32FC3, cv::Scalar(1, 1, 1));
  cv::Mat composite = colourF.mul(alpha3) + white.mul(cv::Scalar(1, 1, 1) - alpha3);
  ProductImages out;
  composite.convertTo(out.onWhite, CV_8UC3, 255.0);
  out.transparent = transparent;
  return out;
}

}  // namespace garmcap::pipeline
