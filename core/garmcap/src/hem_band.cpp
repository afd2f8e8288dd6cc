#include "hem_band.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "frame_ops.h"

namespace garmcap::pipeline {
namespace {

// A row is dark when its median lightness is under this share of the skirt's own (a high-low
// dress's back's inside: 0.43-0.6 of its front; a level hem's fold and the shade of the legs
// under it, within the outline: no run of rows over 0.6 cm on five physical rigs).
constexpr double kHemBandShare = 0.7;
// The skirt's own lightness: the lightest of the medians of windows this tall stacked from
// kSkirtFromCm above the lowest edge up to the hip. A high-low skirt's back can show deeper
// than one window (a skirt's 13 cm), and the lightest window is the front's cloth.
constexpr double kSkirtWindowCm = 10.0;
constexpr double kSkirtFromCm = 5.0;
// The band may end this far above the lowest edge (the edge's own rows mix in what is below).
constexpr double kBandEndCm = 1.5;
// Only rows the garment covers across at least this share of the middle span count.
constexpr double kRowCoverShare = 0.5;
// The middle span: the hem's run 3 cm above its lowest edge, less this share at each side.
constexpr double kSideShare = 0.2;
constexpr double kSpanAboveCm = 3.0;

double medianOfRow(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::optional<HemBand> darkBandAboveHem(const cv::Mat& frameBgr, const cv::Mat& garment,
                                        cv::Point2d hemCentre, double highestRow, double pxPerCm) {
  if (frameBgr.empty() || frameBgr.type() != CV_8UC3 || garment.size() != frameBgr.size() ||
      garment.type() != CV_8UC1 || !(pxPerCm > 0))
    return std::nullopt;
  const int hem = static_cast<int>(std::lround(hemCentre.y)) - 1;  // the last covered row
  const int axis = static_cast<int>(std::lround(hemCentre.x));
  const int spanRow = hem - static_cast<int>(std::lround(kSpanAboveCm * pxPerCm));
  if (!maskCovers(garment, spanRow, axis))
    return std::nullopt;
  int a = axis, b = axis;
  while (maskCovers(garment, spanRow, a - 1))
    --a;
  while (maskCovers(garment, spanRow, b + 1))
    ++b;
  const int cut = static_cast<int>(kSideShare * (b - a));
  a += cut;
  b -= cut;
  const int top = std::max(0, static_cast<int>(std::ceil(highestRow)));
  if (b <= a || hem <= top)
    return std::nullopt;
  cv::Mat lab;
  cv::cvtColor(frameBgr(cv::Range(top, hem + 1), cv::Range(a, b + 1)), lab, cv::COLOR_BGR2Lab);
  // The median lightness of each row the garment covers enough of, bottom row last.
  std::vector<std::optional<double>> rows;
  for (int r = top; r <= hem; ++r) {
    std::vector<double> l;
    for (int x = a; x <= b; ++x)
      if (maskCovers(garment, r, x))
        l.push_back(lab.at<cv::Vec3b>(r - top, x - a)[0]);
    rows.push_back(static_cast<double>(l.size()) >= kRowCoverShare * (b - a + 1)
                       ? std::optional<double>(medianOfRow(l))
                       : std::nullopt);
  }
  const int window = std::max(1, static_cast<int>(std::lround(kSkirtWindowCm * pxPerCm)));
  std::optional<double> skirt;
  for (int end =
           static_cast<int>(rows.size()) - static_cast<int>(std::lround(kSkirtFromCm * pxPerCm));
       end > 0; end -= window) {
    std::vector<double> l;
    for (int i = std::max(0, end - window); i < end; ++i)
      if (const auto& row = rows[static_cast<std::size_t>(i)])
        l.push_back(*row);
    if (2 * l.size() >= static_cast<std::size_t>(std::min(end, window)))
      skirt = std::max(skirt.value_or(0.0), medianOfRow(l));
  }
  if (!skirt)
    return std::nullopt;
  const double dark = kHemBandShare * *skirt;
  // From the lowest edge up: rows not covered enough are passed over, then up to kBandEndCm of
  // rows that are not dark, then the band's dark rows until the first that is not.
  const int endSlack = static_cast<int>(std::lround(kBandEndCm * pxPerCm));
  int band = 0, skipped = 0, highest = 0;
  for (int i = static_cast<int>(rows.size()) - 1; i >= 0; --i) {
    const auto& row = rows[static_cast<std::size_t>(i)];
    const bool isDark = row && *row < dark;
    if (isDark) {
      ++band;
      highest = i;
    } else if (band > 0) {
      break;
    } else if (row && ++skipped > endSlack) {
      break;
    }
  }
  if (band == 0)
    return std::nullopt;
  return HemBand{band / pxPerCm, static_cast<double>(top + highest)};
}

}  // namespace garmcap::pipeline
