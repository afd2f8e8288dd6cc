#include "garmcap/pipeline/garment_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/shape.hpp>
#include <stdexcept>

namespace garmcap::pipeline {
namespace {

std::vector<cv::Point> largestContour(const cv::Mat& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  if (contours.empty())
    return {};
  return *std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
}

// Mean distance of `points` in a distance map (px).
double meanDistance(const std::vector<cv::Point>& points, const cv::Mat& distance) {
  if (points.empty())
    return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (const auto& p : points)
    sum += distance.at<float>(p);
  return sum / static_cast<double>(points.size());
}

// Softmax temperature per method: the score difference that makes one type e times likelier.
double temperature(MatchMethod method, double best) {
  switch (method) {
    case MatchMethod::kIou:
      return 0.03;
    case MatchMethod::kChamfer:
      return 0.004;
    case MatchMethod::kShapeContext:
      return std::max(1e-6, 0.1 * std::abs(best));
  }
  return 1;
}

}  // namespace

std::string toString(MatchMethod method) {
  switch (method) {
    case MatchMethod::kIou:
      return "iou";
    case MatchMethod::kChamfer:
      return "chamfer";
    case MatchMethod::kShapeContext:
      return "shape_context";
  }
  return "iou";
}

std::vector<cv::Point2f> resampleContour(const std::vector<cv::Point>& contour, int count) {
  std::vector<cv::Point2f> out;
  if (contour.size() < 3 || count <= 0)
    return out;
  // Start at the top-most (then left-most) point so the sampling is order-independent.
  const auto start = std::min_element(
      contour.begin(), contour.end(),
      [](const auto& a, const auto& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
  std::vector<cv::Point2f> ring;
  ring.reserve(contour.size() + 1);
  for (auto it = start; it != contour.end(); ++it)
    ring.emplace_back(*it);
  for (auto it = contour.begin(); it != start; ++it)
    ring.emplace_back(*it);
  ring.push_back(ring.front());
  std::vector<double> cum(ring.size(), 0.0);
  for (std::size_t i = 1; i < ring.size(); ++i)
    cum[i] = cum[i - 1] + cv::norm(ring[i] - ring[i - 1]);
  const double total = cum.back();
  if (total <= 0)
    return out;
  std::size_t seg = 1;
  for (int k = 0; k < count; ++k) {
    const double s = total * k / count;
    while (seg + 1 < cum.size() && cum[seg] < s)
      ++seg;
    const double len = cum[seg] - cum[seg - 1];
    const double t = len > 0 ? (s - cum[seg - 1]) / len : 0;
    out.push_back(ring[seg - 1] + static_cast<float>(t) * (ring[seg] - ring[seg - 1]));
  }
  return out;
}

double shapeContextDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b) {
  if (a.size() < 10 || b.size() < 10)
    return std::numeric_limits<double>::infinity();
  // The χ² histogram cost is ½Σ(g−h)²/(g+h) (Belongie et al.; the seed's eq. 5.1 squares the
  // denominator by mistake), which is OpenCV's ChiHistogramCostExtractor.
  static thread_local cv::Ptr<cv::ShapeContextDistanceExtractor> extractor =
      cv::createShapeContextDistanceExtractor(12, 4, 0.2f, 2.0f, 3,
                                              cv::createChiHistogramCostExtractor(),
                                              cv::createThinPlateSplineShapeTransformer());
  try {
    return extractor->computeDistance(a, b);
  } catch (const cv::Exception&) {
    // opencv#5076: a gemm assertion for some pairs; no correspondence means no match.
    return std::numeric_limits<double>::infinity();
  }
}

GarmentClassifier::GarmentClassifier(std::vector<ReferenceSilhouette> references,
                                     ClassifierOptions options)
    : options_(options) {
  if (references.empty())
    throw std::invalid_argument("garment classifier: the reference database is empty");
  const cv::Size frame = references.front().mask.size();
  if (frame.area() == 0)
    throw std::invalid_argument("garment classifier: empty reference mask");
  const double scale = static_cast<double>(options_.workHeightPx) / frame.height;
  workSize_ = cv::Size(std::max(1, static_cast<int>(std::lround(frame.width * scale))),
                       options_.workHeightPx);
  for (auto& r : references) {
    if (r.mask.empty() || cv::countNonZero(r.mask) == 0)
      throw std::invalid_argument("garment classifier: reference '" + r.type +
                                  "' has an empty mask");
    Prepared p = prepare(r.mask);
    p.ref = std::move(r);
    p.ref.mask.release();  // only the working-size copy is needed
    refs_.push_back(std::move(p));
  }
}

GarmentClassifier::Prepared GarmentClassifier::prepare(const cv::Mat& mask) const {
  Prepared p;
  cv::resize(mask != 0, p.work, workSize_, 0, 0, cv::INTER_AREA);
  cv::threshold(p.work, p.work, 127, 255, cv::THRESH_BINARY);
  p.contour = largestContour(p.work);
  cv::Mat edges = cv::Mat::zeros(workSize_, CV_8UC1);
  if (!p.contour.empty())
    cv::drawContours(edges, std::vector<std::vector<cv::Point>>{p.contour}, 0, cv::Scalar(255));
  cv::distanceTransform(edges == 0, p.distance, cv::DIST_L2, 3);
  p.samples = resampleContour(p.contour, options_.shapeContextPoints);
  return p;
}

double GarmentClassifier::similarity(const Prepared& q, const Prepared& r,
                                     MatchMethod method) const {
  switch (method) {
    case MatchMethod::kIou: {
      const int inter = cv::countNonZero(q.work & r.work);
      const int uni = cv::countNonZero(q.work | r.work);
      return uni == 0 ? 0.0 : static_cast<double>(inter) / uni;
    }
    case MatchMethod::kChamfer: {
      const double d =
          0.5 * (meanDistance(q.contour, r.distance) + meanDistance(r.contour, q.distance));
      return -d / workSize_.height;
    }
    case MatchMethod::kShapeContext:
      return -shapeContextDistance(q.samples, r.samples);
  }
  return 0;
}

Classification GarmentClassifier::classify(const cv::Mat& garmentMask, MatchMethod method) const {
  Classification out;
  out.type = "unknown";
  if (garmentMask.empty() || cv::countNonZero(garmentMask) == 0)
    return out;
  const Prepared q = prepare(garmentMask);
  // Best reference per type; the winner's attributes come from its best reference.
  std::map<std::string, std::pair<double, const Prepared*>> bestPerType;
  for (const auto& r : refs_) {
    const double s = similarity(q, r, method);
    auto it = bestPerType.find(r.ref.type);
    if (it == bestPerType.end() || s > it->second.first)
      bestPerType[r.ref.type] = {s, &r};
  }
  std::vector<std::pair<double, const Prepared*>> ranked;
  for (const auto& [type, v] : bestPerType)
    ranked.push_back(v);
  std::sort(ranked.begin(), ranked.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  const auto& [best, bestRef] = ranked.front();
  out.bestScore = best;
  if (ranked.size() > 1) {
    out.runnerUp = ranked[1].second->ref.type;
    out.runnerUpScore = ranked[1].first;
  }
  if (!std::isfinite(best))
    return out;
  const double t = temperature(method, best);
  double z = 0;
  for (const auto& [s, r] : ranked)
    z += std::isfinite(s) ? std::exp((s - best) / t) : 0.0;
  out.confidence = 1.0 / z;

  // "Unknown" is decided on the geometry of the best reference whatever the ranking method, so
  // that a poor overall match is never forced into a type.
  const double iou = similarity(q, *bestRef, MatchMethod::kIou);
  const double chamfer = -similarity(q, *bestRef, MatchMethod::kChamfer);
  if (iou < options_.minIou || chamfer > options_.maxChamferFrac) {
    out.confidence = 0;
    return out;
  }
  out.type = bestRef->ref.type;
  out.attributes = bestRef->ref.attributes;
  return out;
}

}  // namespace garmcap::pipeline
