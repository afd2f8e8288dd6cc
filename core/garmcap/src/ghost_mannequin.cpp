#include "garmcap/pipeline/ghost_mannequin.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace garmcap::pipeline {
namespace {

// The highest garment pixel among columns [x0, x1), of those the one nearest column `near`.
std::optional<cv::Point> highestNear(const cv::Mat1b& garment, int x0, int x1, int near) {
  for (int y = 0; y < garment.rows; ++y) {
    const uchar* g = garment.ptr(y);
    std::optional<cv::Point> best;
    for (int x = std::max(0, x0); x < std::min(garment.cols, x1); ++x)
      if (g[x] && (!best || std::abs(x - near) < std::abs(best->x - near)))
        best = cv::Point(x, y);
    if (best)
      return best;
  }
  return std::nullopt;
}

}  // namespace

NeckOpening neckOpening(const cv::Mat1b& garment, double axisX) {
  NeckOpening out;
  const int axis = static_cast<int>(std::lround(axisX));
  const auto left = highestNear(garment, 0, axis, axis);
  const auto right = highestNear(garment, axis + 1, garment.cols, axis);
  if (!left || !right) {
    out.whyNone = "the garment does not reach both sides of the form's axis";
    return out;
  }
  const cv::Rect box = cv::boundingRect(garment);
  // Rows below the lid: y > lid(x) on the segment from the left to the right neck point.
  auto lidRow = [&](int x) {
    const double t = static_cast<double>(x - left->x) / std::max(1, right->x - left->x);
    return left->y + t * (right->y - left->y);
  };
  cv::Mat1b free = cv::Mat1b::zeros(garment.size());
  for (int x = left->x + 1; x < right->x; ++x) {
    const int y0 = static_cast<int>(std::floor(lidRow(x))) + 1;
    for (int y = std::max(0, y0); y < box.y + box.height; ++y)
      if (!garment(y, x))
        free(y, x) = 255;
  }
  // Flood from the row just below the lid through free pixels (4-connected: a diagonal gap in the
  // outline is no way out).
  cv::Mat1b region = cv::Mat1b::zeros(garment.size());
  std::vector<cv::Point> stack;
  for (int x = left->x + 1; x < right->x; ++x) {
    const int y = static_cast<int>(std::floor(lidRow(x))) + 1;
    if (y >= 0 && y < garment.rows && free(y, x)) {
      region(y, x) = 255;
      stack.emplace_back(x, y);
    }
  }
  int deepest = -1;
  while (!stack.empty()) {
    const cv::Point p = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, p.y);
    const cv::Point next[] = {{p.x + 1, p.y}, {p.x - 1, p.y}, {p.x, p.y + 1}, {p.x, p.y - 1}};
    for (const cv::Point q : next)
      if (q.x >= 0 && q.y >= 0 && q.x < garment.cols && q.y < garment.rows && free(q.y, q.x) &&
          !region(q.y, q.x)) {
        region(q.y, q.x) = 255;
        stack.push_back(q);
      }
  }
  if (deepest < 0) {
    out.whyNone = "the garment has no opening between its neck points";
    return out;
  }
  const double depth = deepest - std::min(left->y, right->y);
  if (depth > kMaxNeckOpeningDepth * box.height) {
    out.whyNone = "the opening between the neck points runs " +
                  std::to_string(static_cast<int>(std::lround(100.0 * depth / box.height))) +
                  " % down the garment: an open front, not a neckline";
    return out;
  }
  out.region = region;
  return out;
}

ProductLayer mirroredLayer(const ProductLayer& layer, const cv::Rect& from, double axisX,
                           const cv::Rect& to) {
  if (layer.colour.size() != from.size() || layer.alpha.size() != from.size())
    throw std::invalid_argument("mirroredLayer: the layer is not the size of its rectangle");
  // dst(x, y) = src(2 axisX - to.x - x - from.x, to.y + y - from.y)
  const cv::Matx23d inverse(-1.0, 0.0, 2.0 * axisX - to.x - from.x, 0.0, 1.0, to.y - from.y);
  ProductLayer out;
  cv::warpAffine(layer.colour, out.colour, inverse, to.size(),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  cv::warpAffine(layer.alpha, out.alpha, inverse, to.size(),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

int composeGhostFront(ProductLayer& front, const ProductLayer& inside, const cv::Mat1b& opening,
                      int rimPx) {
  const cv::Size size = front.colour.size();
  if (front.alpha.size() != size || inside.colour.size() != size || inside.alpha.size() != size ||
      opening.size() != size)
    throw std::invalid_argument("composeGhostFront: the layers and the opening differ in size");
  cv::Mat1b where = opening.clone();
  if (rimPx > 0) {
    cv::Mat1b rim;
    cv::dilate(
        opening, rim,
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * rimPx + 1, 2 * rimPx + 1)));
    where |= rim & (front.alpha < 1.0f);
  }
  const float shade = static_cast<float>(kGhostInsideShade);
  int changed = 0;
  for (int y = 0; y < size.height; ++y) {
    const uchar* w = where.ptr(y);
    float* af = front.alpha.ptr<float>(y);
    cv::Vec3b* f = front.colour.ptr<cv::Vec3b>(y);
    const float* ai = inside.alpha.ptr<float>(y);
    const cv::Vec3b* b = inside.colour.ptr<cv::Vec3b>(y);
    for (int x = 0; x < size.width; ++x) {
      if (!w[x] || af[x] >= 1.0f || ai[x] <= 0.0f)
        continue;
      const float behind = (1.0f - af[x]) * std::min(ai[x], 1.0f);
      const float a = af[x] + behind;
      for (int c = 0; c < 3; ++c)
        f[x][c] = cv::saturate_cast<uchar>((af[x] * f[x][c] + behind * shade * b[x][c]) / a);
      af[x] = a;
      ++changed;
    }
  }
  return changed;
}

}  // namespace garmcap::pipeline
