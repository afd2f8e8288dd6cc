#pragma once
// Segmenting the bare form (or anything) in front of the green screen (seed §5.2.1).
//
// Keying works on greenness g = G - max(R, B), a linear function of the pixel colour as long as
// green dominates, so an edge pixel that mixes screen and form has g between the two and its
// coverage is recovered by unmixing: alpha = (g_screen - g) / (g_screen - g_form). The screen's
// greenness is estimated per pixel from the visible screen (smooth normalised convolution), so
// an unevenly lit screen keys as well as an even one; the form's greenness likewise from nearby
// form pixels. The screen colour is first checked on the frame border.

#include <opencv2/core.hpp>

namespace garmcap::calib {

struct KeyOptions {
  double borderFraction = 0.02;          // width of the border ring sampled for the screen colour
  double minForegroundFraction = 0.002;  // less than this of the frame: "no form in frame"
  int edgeBandPx = 2;                    // soft alpha only within this distance of the binary edge
  // Stations frame the garment, not the whole form: the form's legs, feet or stand may run out
  // of the frame at the bottom. When false, a foreground touching the bottom edge is refused as
  // one touching the top or the sides always is.
  bool allowCutAtBottom = true;
};

struct KeyResult {
  cv::Mat1f alpha;      // foreground coverage 0..1 (the largest foreground component only)
  cv::Mat1b mask;       // alpha > 0.5, 0/255
  cv::Mat3b despilled;  // the frame with green spill removed from the foreground (G <= max(R,B))
  cv::Vec3b screenBgr;  // median border colour
  double screenHueDeg = 0;  // its hue, 0..360
  cv::Mat1f
      screenGreenness;  // the screen's greenness G - max(R, B) per pixel, at this frame's size
  // The foreground's own luminance near its edge (from pixels inside it), at half resolution over
  // formLuminanceRoi (this frame's px): with the screen's luminance it unmixes edge pixels that
  // spill has tinted green.
  cv::Mat1f formLuminance;
  cv::Rect formLuminanceRoi;
  // The foreground runs out of the frame at its bottom edge (legs, feet or a stand below it).
  bool cutAtBottom = false;
};

/// Keys `frameBgr` (8-bit BGR). Throws CalibError kNotGreenScreen when the border is not a
/// saturated green, kNoFormInFrame when the foreground is smaller than minForegroundFraction, and
/// kFormCutOff when the foreground touches the top or a side of the frame (or the bottom, unless
/// options.allowCutAtBottom). `what` names the frame in messages.
KeyResult keyGreenScreen(const cv::Mat3b& frameBgr, const std::string& what,
                         const KeyOptions& options = {});

/// What stands in front of the screen, at full resolution, for the pixels set in `where` only:
/// a pixel is foreground when its greenness is below half the screen's there. `workKey` is the
/// key of a downscaled copy of `fullBgr`; its screen greenness varies slowly, so it is sampled at
/// the pixel's place in the small frame. This lets a pipeline key ~1 MP and still place edges
/// against the screen to the full frame's pixel. Returns CV_8U of fullBgr's size, 255 =
/// foreground, 0 elsewhere (and everywhere outside `where`). Throws std::invalid_argument on
/// mismatched sizes.
cv::Mat1b foregroundInRegion(const cv::Mat3b& fullBgr, const KeyResult& workKey,
                             const cv::Mat1b& where);

/// Removes green spill in place where `mask` is set: green may not exceed the larger of red and
/// blue there.
void despill(cv::Mat3b& bgr, const cv::Mat1b& mask);

}  // namespace garmcap::calib
