#pragma once
// The screen-coloured garment's fallback (internal to the pipeline). A garment close to the
// screen's colour (dark or olive green) keys as screen where it hangs over the screen, and over
// the form wherever it is lit well. Found over the form (where the form cannot vanish), every
// pixel where the dressed frame differs from the bare screen becomes GrabCut's to decide, and
// what GrabCut cut is repaired afterwards.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/calib/chroma_key.h"

namespace garmcap::pipeline {

/// Where both keys see the screen, how the dressed frame differs from the bare one beyond sensor
/// noise: `changed` by the largest per-channel log ratio, `recoloured` by their spread.
struct ScreenChange {
  cv::Mat changed, recoloured;
};

/// The screen's change when the garment is screen-coloured (more than kScreenColouredCm2 of the
/// form's inside `formInside` keys as screen in `keyD`), with its warning added to `warnings`;
/// nullopt for other garments. `fgD` is the dressed foreground, `formOutline` the form's mixed
/// outline pixels, `pxPerCm` the work frame's scale.
std::optional<ScreenChange> screenColouredChange(const calib::KeyResult& keyE,
                                                 const calib::KeyResult& keyD,
                                                 const cv::Mat& formInside,
                                                 const cv::Mat& formOutline, const cv::Mat& fgD,
                                                 double pxPerCm,
                                                 std::vector<std::string>& warnings);

/// GrabCut's garment `garmentW` for a screen-coloured garment: of the changed screen only the
/// regions beyond the key's outline, and the notches a pattern's screen-coloured squares leave in
/// its sides closed along the vertical where the frame changed.
cv::Mat repairScreenColouredGarment(const cv::Mat& garmentW, const cv::Mat& fgD,
                                    const cv::Mat& exposed, const ScreenChange& change,
                                    double pxPerCm);

}  // namespace garmcap::pipeline
