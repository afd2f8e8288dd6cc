#include "garmcap/capture/frame.h"

#include <stdexcept>

namespace garmcap::capture {

const char* toString(Shot shot) {
  switch (shot) {
    case Shot::kAny:
      return "any";
    case Shot::kEmpty:
      return "empty";
    case Shot::kDressed:
      return "dressed";
  }
  return "?";
}

void requireSameSize(const cv::Mat& empty, const cv::Mat& dressed, const std::string& what) {
  if (empty.empty() || dressed.empty()) {
    throw std::invalid_argument(what + ": " + (empty.empty() ? "empty" : "dressed") +
                                " frame has no pixels");
  }
  if (empty.size() != dressed.size()) {
    throw std::invalid_argument(what + ": empty frame is " + std::to_string(empty.cols) + "x" +
                                std::to_string(empty.rows) + " but dressed frame is " +
                                std::to_string(dressed.cols) + "x" + std::to_string(dressed.rows) +
                                "; both must come from the same camera mode to be compared");
  }
}

}  // namespace garmcap::capture
