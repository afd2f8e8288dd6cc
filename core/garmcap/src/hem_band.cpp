#include "hem_band.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

namespace garmcap::pipeline {
namespace {

// A row is dark when its median lightness is under this share of the skirt's own (a high-low
// dress's back's inside: 0.43-0.6 of its front; a level hem's fold and the shade of the legs
// under it, within the outline: no run of rows over 0.6 cm on five physical rigs).
constexpr double kHemBandShare = 0.7;
// The band is looked for over this height above the lowest edge; the skirt's lightness is the
// median of the rows from kSearchCm to kSkirtToCm above it.
constexpr double kSearchCm = 15.0;
constexpr double kSkirtToCm = 5.0;
// The band may end this far above the lowest edge (the edge's own rows mix in what is below).
constexpr double kBandEndCm = 1.5;
// Only rows the garment covers across at least this share of the middle span count.
constexpr double kRowCoverShare = 0.5;
// The middle span: the hem's run 3 cm above its lowest edge, less this share at each side.
constexpr double kSideShare = 0.2;
constexpr double kSpanAboveCm = 3.0;

bool covers(const cv::Mat& m, int r, int c) {
  return r >= 0 && r < m.rows && c >= 0 && c < m.cols && m.at<std::uint8_t>(r, c) != 0;
}

double medianOfRow(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

double darkBandAboveHemCm(const cv::Mat& frameBgr, const cv::Mat& garment, cv::Point2d hemCentre,
                          double pxPerCm) {
  if (frameBgr.empty() || frameBgr.type() != CV_8UC3 || garment.size() != frameBgr.size() ||
      garment.type() != CV_8UC1 || !(pxPerCm > 0))
    return 0;
  const int hem = static_cast<int>(std::lround(hemCentre.y)) - 1;  // the last covered row
  const int axis = static_cast<int>(std::lround(hemCentre.x));
  const int spanRow = hem - static_cast<int>(std::lround(kSpanAboveCm * pxPerCm));
  if (!covers(garment, spanRow, axis))
    return 0;
  int a = axis, b = axis;
  while (covers(garment, spanRow, a - 1))
    --a;
  while (covers(garment, spanRow, b + 1))
    ++b;
  const int cut = static_cast<int>(kSideShare * (b - a));
  a += cut;
  b -= cut;
  const int top = std::max(0, hem - static_cast<int>(std::lround(kSearchCm * pxPerCm)));
  if (b <= a || hem <= top)
    return 0;
  cv::Mat lab;
  cv::cvtColor(frameBgr(cv::Range(top, hem + 1), cv::Range(a, b + 1)), lab, cv::COLOR_BGR2Lab);
  // The median lightness of each row the garment covers enough of, bottom row last.
  std::vector<std::optional<double>> rows;
  for (int r = top; r <= hem; ++r) {
    std::vector<double> l;
    for (int x = a; x <= b; ++x)
      if (covers(garment, r, x))
        l.push_back(lab.at<cv::Vec3b>(r - top, x - a)[0]);
    rows.push_back(static_cast<double>(l.size()) >= kRowCoverShare * (b - a + 1)
                       ? std::optional<double>(medianOfRow(l))
                       : std::nullopt);
  }
  std::vector<double> skirt;
  const auto skirtRows = static_cast<std::size_t>(std::lround((kSearchCm - kSkirtToCm) * pxPerCm));
  for (std::size_t i = 0; i < std::min(skirtRows, rows.size()); ++i)
    if (rows[i])
      skirt.push_back(*rows[i]);
  if (skirt.empty())
    return 0;
  const double dark = kHemBandShare * medianOfRow(skirt);
  // From the lowest edge up: rows not covered enough are passed over, then up to kBandEndCm of
  // rows that are not dark, then the band's dark rows until the first that is not.
  const int endSlack = static_cast<int>(std::lround(kBandEndCm * pxPerCm));
  int band = 0, skipped = 0;
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) {
    const bool isDark = *it && **it < dark;
    if (isDark) {
      ++band;
    } else if (band > 0) {
      break;
    } else if (*it && ++skipped > endSlack) {
      break;
    }
  }
  return band / pxPerCm;
}

}  // namespace garmcap::pipeline
