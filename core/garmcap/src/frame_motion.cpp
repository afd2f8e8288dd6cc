#include "garmcap/pipeline/frame_motion.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace garmcap::pipeline {
namespace {

// A roll read from the frame's bands beyond this is taken for a misreading.
constexpr double kMaxRollRad = 0.01;
// Bands thinner than this (edge-image rows) give no roll.
constexpr int kMinBandRows = 32;

// The edge image's scale: about 0.5 MP, where phase correlation still reads a tenth of a pixel.
double motionScale(const cv::Size& size) {
  return std::min(1.0, std::sqrt(0.5e6 / static_cast<double>(size.area())));
}

cv::Mat motionEdges(const cv::Mat& bgr, double scale) {
  cv::Mat g, small, gx, gy, mag;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  cv::resize(g, small, cv::Size(), scale, scale, cv::INTER_AREA);
  small.convertTo(small, CV_32F);
  cv::GaussianBlur(small, small, cv::Size(3, 3), 0);
  cv::Sobel(small, gx, CV_32F, 1, 0);
  cv::Sobel(small, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, mag);
  return mag;
}

// OpenCV 4.6's phaseCorrelate multiplies its inputs by the window in place when their size is
// already one its DFT takes (no padded copy is made): the bare frame's edges, kept for the life
// of a calibration, then faded towards the window's centre with every capture, and after nine
// captures at 480x640 a garment's print outweighed them ("the camera moved by 47.9 px"). Each
// call gets copies.
cv::Point2d phaseShift(const cv::Mat& reference, const cv::Mat& moved, const cv::Mat& window) {
  return cv::phaseCorrelate(reference.clone(), moved.clone(), window);
}

}  // namespace

double FrameMotion::largestPx(double halfHeight) const {
  return std::hypot(shift.x, shift.y) + std::abs(rollRad) * halfHeight;
}

cv::Matx33d FrameMotion::registration(const cv::Size& measuredOn, double scale) const {
  const cv::Point2d c(0.5 * (measuredOn.width - 1) * scale, 0.5 * (measuredOn.height - 1) * scale);
  const double cs = std::cos(rollRad), sn = std::sin(rollRad);
  // R(-roll) = [cs sn; -sn cs]; p_bare = c + R (p - c - t).
  const cv::Point2d t = shift * scale;
  const cv::Point2d ct(c.x + t.x, c.y + t.y);
  return {cs, sn, c.x - (cs * ct.x + sn * ct.y), -sn, cs, c.y - (-sn * ct.x + cs * ct.y), 0, 0, 1};
}

MotionReference::MotionReference(const cv::Mat& bareBgr, int topEndRow, int bottomStartRow)
    : frameSize_(bareBgr.size()), scale_(motionScale(bareBgr.size())) {
  if (bareBgr.empty() || bareBgr.type() != CV_8UC3)
    throw std::invalid_argument("MotionReference: the bare frame is not an 8-bit colour image");
  edges_ = motionEdges(bareBgr, scale_);
  whole_ = region(cv::Rect(0, 0, edges_.cols, edges_.rows));
  const int t1 = std::clamp(static_cast<int>(topEndRow * scale_), 0, edges_.rows);
  const int b0 = std::clamp(static_cast<int>(bottomStartRow * scale_), 0, edges_.rows);
  bands_ = t1 >= kMinBandRows && edges_.rows - b0 >= kMinBandRows && b0 - t1 >= kMinBandRows;
  topOnly_ = !bands_ && bottomStartRow >= bareBgr.rows && t1 >= kMinBandRows;
  bottomOnly_ = !bands_ && !topOnly_ && bottomStartRow < bareBgr.rows &&
                edges_.rows - b0 >= kMinBandRows && b0 >= kMinBandRows;
  if (bands_ || topOnly_)
    top_ = region(cv::Rect(0, 0, edges_.cols, t1));
  if (bands_ || bottomOnly_)
    bottom_ = region(cv::Rect(0, b0, edges_.cols, edges_.rows - b0));
}

// OpenCV's phaseCorrelate can read up to half a pixel off (it finds 0.5 for some edge images
// against themselves: its sub-pixel centroid does not wrap around a peak at zero shift), so
// each region's reading of itself is kept and taken off.
MotionReference::Region MotionReference::region(const cv::Rect& rect) const {
  Region r;
  r.rect = rect;
  cv::createHanningWindow(r.window, rect.size(), CV_32F);
  r.selfReading = phaseShift(edges_(rect), edges_(rect), r.window);
  return r;
}

cv::Point2d MotionReference::shiftOf(const Region& r, const cv::Mat& dressedEdges) const {
  return phaseShift(edges_(r.rect), dressedEdges(r.rect), r.window) - r.selfReading;
}

// The parts no garment changes (screen texture, head, arms, legs, the stand) agree at the true
// motion, and phase correlation is robust to the garment, which changes only a part of the
// picture. A roll moves the top and bottom bands sideways in opposite directions.
FrameMotion MotionReference::motionOf(const cv::Mat& dressedBgr) const {
  if (dressedBgr.size() != frameSize_ || dressedBgr.type() != CV_8UC3)
    throw std::invalid_argument(
        "MotionReference: the dressed frame is " + std::to_string(dressedBgr.cols) + "x" +
        std::to_string(dressedBgr.rows) + " but the bare frame " +
        std::to_string(frameSize_.width) + "x" + std::to_string(frameSize_.height));
  const cv::Mat b = motionEdges(dressedBgr, scale_);
  FrameMotion m;
  if (topOnly_ || bottomOnly_) {
    m.shift = shiftOf(topOnly_ ? top_ : bottom_, b) / scale_;
    return m;
  }
  m.shift = shiftOf(whole_, b) / scale_;
  if (!bands_)
    return m;
  const cv::Point2d dTop = shiftOf(top_, b), dBottom = shiftOf(bottom_, b);
  const double yTop = top_.rect.y + 0.5 * top_.rect.height;
  const double yBottom = bottom_.rect.y + 0.5 * bottom_.rect.height;
  const double roll = -(dBottom.x - dTop.x) / (yBottom - yTop);
  if (std::abs(roll) > kMaxRollRad)
    return m;
  m.rollRad = roll;
  // The shift at the centre, interpolated between the two bands.
  const double f = (0.5 * (b.rows - 1) - yTop) / (yBottom - yTop);
  m.shift = (dTop + f * (dBottom - dTop)) / scale_;
  return m;
}

}  // namespace garmcap::pipeline
