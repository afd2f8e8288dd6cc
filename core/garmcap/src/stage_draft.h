#pragma once
// Stage 7 of a capture: the garment's pattern, drafted for the form's body (internal).

#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {

/// Sets `result.pattern` from its type, attributes and measurements; a garment the recipes cannot
/// draft gets no pattern and a warning saying why (the capture still stands).
void draftCapturedGarment(const CaptureContext& ctx, CaptureResult& result);

}  // namespace garmcap::pipeline
