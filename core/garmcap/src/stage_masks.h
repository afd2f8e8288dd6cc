#pragma once
// Stage 3 of a capture: the masks (seed 5.2.2) from the two keyed work frames: the form (bare
// frame), the form still exposed in the dressed frame (it looks as it did), the garment's shadow
// on the form, and the base mask of the garment, turned into a GrabCut trimap (internal).

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bare_frame.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/pipeline/garment_measurer.h"
#include "stage_screen_coloured.h"

namespace garmcap::pipeline {

struct GarmentMasks {
  cv::Mat form;        // the bare frame's key: the form
  cv::Mat foreground;  // the dressed frame's foreground, the form's inside included
  cv::Mat exposed;     // form that looks as in the bare frame
  std::optional<ScreenChange> screenChange;  // set for a screen-coloured garment
  cv::Mat trimap;                            // GrabCut's labels (cv::GC_*)
};

/// The masks of the work frames keyed as `keyE` (bare) and `keyD` (dressed). Throws CaptureError
/// kNoGarment when the dressed frame shows the bare form. Set GARMCAP_DEBUG_DIR to have the
/// intermediate masks written there as PNG.
GarmentMasks garmentMasks(const calib::KeyResult& keyE, const calib::KeyResult& keyD,
                          const FormView& view, const WorkGeometry& g,
                          std::vector<std::string>& warnings);

}  // namespace garmcap::pipeline
