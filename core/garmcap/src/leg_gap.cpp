#include "leg_gap.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace garmcap::pipeline {
namespace {

// The slit is looked for with its darkest pixel within this distance of the body axis.
constexpr double kSlitReachCm = 2.0;
// The garment beside the slit is sampled from this far to this far from its darkest pixel.
constexpr double kFlankFromCm = 1.0;
constexpr double kFlankToCm = 3.0;
// A slit row: its darkest pixel has at most this share of the lightness of the brighter flank
// (a local dark line), and of the garment's own darkest fabric on the seat (kSeatPercentile of
// the lightness between hip and crotch): the cavity between two legs is self-shadowed, darker
// than any colour of the garment, where a print's dot or a stripe is one of its colours.
constexpr double kSlitShareOfFlank = 0.4;
constexpr double kSlitShareOfSeat = 0.5;
constexpr double kSeatPercentile = 0.05;
// The seat is sampled within this distance of the axis (wider than any form's hip).
constexpr double kSeatHalfWidthCm = 25.0;
// The slit starts within this distance below the form's crotch (pants part there; the seat's
// ease hangs the garment's crotch a few cm lower), runs at least this long (the shortest
// shorts' inseam, as the type stage's kPartedLegsCm) and may be interrupted (a fold, a bright
// check across it) for at most this long.
constexpr double kSlitStartCm = 5.0;
constexpr double kSlitMinCm = 5.0;
constexpr double kSlitBreakCm = 1.0;
// The carved gap is at least this wide around the axis, as partedLegsCm reads the centre line.
constexpr double kCarveHalfCm = 0.5;

struct SlitRow {
  int row = 0;
  int lo = 0, hi = 0;  // the slit's columns (inclusive)
};

double medianOf(std::vector<double> v) {
  auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

double carveGapBetweenLegs(cv::Mat& garment, const cv::Mat& dressedBgr, const FormView& view,
                           std::vector<std::string>& warnings) {
  if (!view.crotchCm() || garment.empty())
    return 0.0;
  const double s = view.pose().pxPerCm;
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  const int reach = static_cast<int>(std::lround(kSlitReachCm * s));
  const int flankFrom = std::max(1, static_cast<int>(std::lround(kFlankFromCm * s)));
  const int flankTo = static_cast<int>(std::lround(kFlankToCm * s));
  const int crotchRow = static_cast<int>(std::lround(view.rowOfHeight(*view.crotchCm())));
  const int hipRow = static_cast<int>(std::lround(view.rowOfHeight(view.hipCm())));
  if (hipRow < 0 || crotchRow <= hipRow || crotchRow >= garment.rows ||
      axis - reach - flankTo < 0 || axis + reach + flankTo >= garment.cols ||
      dressedBgr.size() != garment.size())
    return 0.0;
  // Lightness, lightly smoothed against sensor noise, over the part of the frame the seat and the
  // slit can be in (a whole 12 MP frame costs tens of ms).
  const int seatHalf = static_cast<int>(std::lround(kSeatHalfWidthCm * s));
  const cv::Rect roi = cv::Rect(axis - seatHalf, hipRow, 2 * seatHalf + 1, garment.rows - hipRow) &
                       cv::Rect(0, 0, garment.cols, garment.rows);
  cv::Mat gray;
  cv::cvtColor(dressedBgr(roi), gray, cv::COLOR_BGR2GRAY);
  cv::GaussianBlur(gray, gray, cv::Size(), std::max(0.6, 0.1 * s));
  std::vector<double> seat;
  for (int r = hipRow; r < crotchRow; ++r) {
    const uchar* m = garment.ptr(r);
    const uchar* l = gray.ptr(r - roi.y);
    for (int x = roi.x; x < roi.x + roi.width; ++x)
      if (m[x])
        seat.push_back(l[x - roi.x]);
  }
  if (seat.size() < 100)
    return 0.0;
  const auto pos = seat.begin() + static_cast<long>(kSeatPercentile * (seat.size() - 1));
  std::nth_element(seat.begin(), pos, seat.end());
  const double seatDark = *pos;

  const int startLimit = crotchRow + static_cast<int>(std::lround(kSlitStartCm * s));
  const int maxBreak = static_cast<int>(std::lround(kSlitBreakCm * s));
  std::vector<SlitRow> slit;
  for (int r = crotchRow; r < garment.rows; ++r) {
    if (slit.empty() ? r > startLimit : r - slit.back().row > maxBreak)
      break;
    const uchar* m = garment.ptr(r);
    // Lightness by frame column (the ROI holds every column used below).
    const uchar* row = gray.ptr(r - roi.y);
    auto l = [&](int x) { return static_cast<double>(row[x - roi.x]); };
    int xm = -1;
    for (int x = axis - reach; x <= axis + reach; ++x)
      if (m[x] && (xm < 0 || l(x) < l(xm)))
        xm = x;
    if (xm < 0)
      continue;
    std::vector<double> lv, rv;
    for (int x = xm - flankTo; x <= xm - flankFrom; ++x)
      if (m[x])
        lv.push_back(l(x));
    for (int x = xm + flankFrom; x <= xm + flankTo; ++x)
      if (m[x])
        rv.push_back(l(x));
    const int need = (flankTo - flankFrom) / 2;
    if (static_cast<int>(lv.size()) <= need || static_cast<int>(rv.size()) <= need)
      continue;
    const double flank = std::max(medianOf(lv), medianOf(rv));
    if (l(xm) > kSlitShareOfFlank * flank || l(xm) > kSlitShareOfSeat * seatDark)
      continue;
    // The slit's extent: darker than half-way between its darkest pixel and the flank.
    const double edge = 0.5 * (l(xm) + flank);
    int lo = xm, hi = xm;
    while (lo - 1 > xm - flankFrom && l(lo - 1) < edge)
      --lo;
    while (hi + 1 < xm + flankFrom && l(hi + 1) < edge)
      ++hi;
    slit.push_back({r, lo, hi});
  }
  if (slit.empty())
    return 0.0;
  const double lengthCm = (slit.back().row - slit.front().row + 1) / s;
  if (lengthCm < kSlitMinCm)
    return 0.0;
  // Interruptions are carved too: the gap is one piece from its top to its bottom.
  const int half = static_cast<int>(std::lround(kCarveHalfCm * s));
  for (std::size_t i = 0; i < slit.size(); ++i) {
    const int lo = std::min(slit[i].lo, axis - half), hi = std::max(slit[i].hi, axis + half);
    const int until = i + 1 < slit.size() ? slit[i + 1].row : slit[i].row + 1;
    for (int r = slit[i].row; r < until; ++r)
      garment.row(r).colRange(lo, hi + 1).setTo(0);
  }
  warnings.push_back(
      "the garment shows a dark slit down from the crotch for " +
      std::to_string(static_cast<int>(std::lround(lengthCm))) +
      " cm, taken for the gap between the legs (legs that touch, or the gap's top in shadow)");
  return lengthCm;
}

}  // namespace garmcap::pipeline
