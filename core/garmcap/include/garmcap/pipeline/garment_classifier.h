#pragma once
// Garment type and attributes from the garment silhouette (seed §5.2.3). Camera and form are
// fixed, so a captured silhouette is already registered with silhouettes of known garments
// rendered on the same calibrated form: we rank them by mask IoU and by chamfer distance, and
// also by Shape Context (the seed's method, with eq. 5.1's χ² numerator corrected to (g−h)²)
// so the two can be compared on rigs. A garment that matches nothing well is "unknown".

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace garmcap::pipeline {

/// A silhouette of a known garment on the calibrated form, frame-sized or any size with the
/// frame's aspect ratio (it is resampled to the classifier's working size).
struct ReferenceSilhouette {
  std::string type;                               // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve, skirt
  cv::Mat mask;                                   // CV_8U, non-zero = garment
};

enum class MatchMethod { kIou, kChamfer, kShapeContext };
std::string toString(MatchMethod method);

struct Classification {
  std::string type;  // "unknown" when no reference matches well enough
  std::map<std::string, std::string> attributes;
  double confidence = 0;  // 0..1, from the best score and its margin over the runner-up type
  std::string runnerUp;
  double bestScore = 0;  // method's similarity of the best reference (IoU: 0..1)
  double runnerUpScore = 0;
};

struct ClassifierOptions {
  int workHeightPx = 320;        // silhouettes are compared at this height
  double minIou = 0.55;          // below this the garment is "unknown"
  double maxChamferFrac = 0.06;  // mean chamfer distance / work height above which "unknown"
  int shapeContextPoints = 100;  // contour samples for Shape Context
};

class GarmentClassifier {
 public:
  /// Throws std::invalid_argument when `references` is empty or a mask is empty.
  GarmentClassifier(std::vector<ReferenceSilhouette> references, ClassifierOptions options = {});

  /// Classifies a frame-sized garment mask with one method.
  Classification classify(const cv::Mat& garmentMask, MatchMethod method) const;

  std::size_t size() const { return refs_.size(); }

 private:
  struct Prepared {
    ReferenceSilhouette ref;
    cv::Mat work;      // CV_8U 0/255 at the working size
    cv::Mat distance;  // distance transform to the reference's contour
    std::vector<cv::Point> contour;
    std::vector<cv::Point2f> samples;  // arc-length samples for Shape Context
  };
  Prepared prepare(const cv::Mat& mask) const;
  double similarity(const Prepared& query, const Prepared& ref, MatchMethod method) const;

  ClassifierOptions options_;
  cv::Size workSize_;
  std::vector<Prepared> refs_;
};

/// Shape Context distance between two point sets (Belongie, Malik & Puzicha 2002) computed with
/// OpenCV's shape module; OpenCV throws for some pairs (opencv#5076): those return +infinity.
double shapeContextDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b);

/// `count` points at equal arc length along a closed contour, starting at its top-most point
/// (deterministic, so the distance does not depend on where findContours starts).
std::vector<cv::Point2f> resampleContour(const std::vector<cv::Point>& contour, int count);

}  // namespace garmcap::pipeline
