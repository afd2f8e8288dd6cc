#pragma once
// Whether and how the camera moved between the bare-form frame and the dressed frame: a shift and
// a small roll, read by phase correlation of the two frames' edge images. A bumped tripod turns a
// little as well as shifting; a roll of 0.06 degrees already moves the feet of a 4 MP frame by a
// pixel, which the exposed-form test would read as a garment.

#include <opencv2/core.hpp>

namespace garmcap::pipeline {

/// How the dressed frame moved against the bare one: dressed content at p was at
/// c + R(-rollRad) (p - c - shift) in the bare frame, c the centre of the frame it was measured on
/// (in that frame's pixels).
struct FrameMotion {
  cv::Point2d shift;
  double rollRad = 0;

  /// The largest displacement the motion causes within `halfHeight` px of the centre.
  double largestPx(double halfHeight) const;
  /// The 3x3 (affine) forward map that takes the dressed frame back onto the bare one, for a
  /// frame `scale` times the size of `measuredOn` (the frame the motion was measured on).
  cv::Matx33d registration(const cv::Size& measuredOn, double scale) const;
};

/// The bare frame's side of the estimate, prepared once per bare frame (edge image at about
/// 0.5 MP, windows, and phase correlation's own reading of each region against itself).
/// The shift comes from the whole frame; the roll from the horizontal shifts of a top band (rows
/// above `topEndRow`) and a bottom band (rows from `bottomStartRow`), where no garment reaches
/// (the head, the feet); rows in the bare frame's pixels. With bands under 32 edge rows, or a
/// roll read above 0.01 rad (a misreading: the caller's shift check refuses a camera that really
/// moved), the roll is 0 and the shift the whole frame's. With no bottom band at all
/// (`bottomStartRow` at or below the frame's last row: the frame cuts the form's legs, and its
/// bottom rows may hold a skirt) the shift is the top band's alone, when it is 32 edge rows or
/// more: the whole frame's reading is pulled by the garment, which then fills much of it. Likewise
/// with a top band under 32 edge rows (a torso form framed close to its neck cap) the shift is the
/// bottom band's alone: a form-coloured dress on such a form pulled the whole frame's reading to
/// 4.6-5.9 px with the camera still (tests/data/motion).
class MotionReference {
 public:
  MotionReference(const cv::Mat& bareBgr, int topEndRow, int bottomStartRow);

  /// Motion of `dressedBgr` (the bare frame's size and type) against the bare frame.
  /// Throws std::invalid_argument for a frame of another size.
  FrameMotion motionOf(const cv::Mat& dressedBgr) const;

 private:
  struct Region {
    cv::Rect rect;
    cv::Mat window;
    cv::Point2d selfReading;
  };
  cv::Size frameSize_;
  double scale_ = 1;
  cv::Mat edges_;
  Region whole_, top_, bottom_;
  bool bands_ = false;
  bool topOnly_ = false;     // no bottom band: the shift from the top band
  bool bottomOnly_ = false;  // no top band: the shift from the bottom band

  Region region(const cv::Rect& rect) const;
  cv::Point2d shiftOf(const Region& r, const cv::Mat& dressedEdges) const;
};

}  // namespace garmcap::pipeline
