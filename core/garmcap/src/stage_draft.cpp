#include "stage_draft.h"

#include <exception>
#include <string>

#include "garmcap/pipeline/draft_from_garment.h"

namespace garmcap::pipeline {

void draftCapturedGarment(const CaptureContext& ctx, CaptureResult& result) {
  const FormView& view = *ctx.view;
  try {
    result.pattern = draftFromGarment(result.type, result.attributes, result.measurements, ctx.body,
                                      view.neckSideCm() - view.waistCm(), result.warnings);
  } catch (const std::exception& e) {
    result.warnings.push_back(std::string("no pattern: ") + e.what());
  }
}

}  // namespace garmcap::pipeline
