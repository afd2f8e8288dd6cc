// Link-time fallbacks for pipeline entry points that are declared in their module's header but
// not implemented yet in a given build. This archive is linked after the real libraries: the
// linker takes a member from here only when no library defined the symbol, so a real
// implementation always wins (the definitions are also weak). A job that reaches a missing
// stage then fails with a message naming it instead of inventing a result.
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {

__attribute__((weak)) CaptureResult runCapture(const cv::Mat&, const cv::Mat&,
                                               const nlohmann::json&, const CaptureOptions&) {
  throw std::runtime_error(
      "GarmCap failed: core/garmcap's runCapture is not implemented in this build");
}

}  // namespace garmcap::pipeline
