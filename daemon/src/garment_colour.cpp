#include "garmcap/daemon/garment_colour.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace garmcap::daemon {
namespace {

struct PaletteEntry {
  const char* name;
  std::array<int, 3> rgb;  // a typical sRGB value of the colour
};

// Basic colour names as shops list them and Merchant Center reads them. Two shades where one
// name would mislead a shopper (navy is not blue, burgundy is not red, olive is not green).
const std::array<PaletteEntry, 18> kPalette = {{{"Black", {22, 22, 24}},
                                                {"White", {246, 246, 244}},
                                                {"Grey", {130, 130, 132}},
                                                {"Beige", {222, 200, 164}},
                                                {"Brown", {112, 72, 42}},
                                                {"Red", {196, 32, 40}},
                                                {"Burgundy", {118, 22, 44}},
                                                {"Pink", {238, 150, 180}},
                                                {"Orange", {238, 128, 34}},
                                                {"Yellow", {240, 210, 50}},
                                                {"Green", {40, 140, 64}},
                                                {"Olive", {110, 112, 44}},
                                                {"Turquoise", {40, 180, 180}},
                                                {"Light blue", {140, 182, 230}},
                                                {"Blue", {40, 90, 200}},
                                                {"Navy", {26, 36, 84}},
                                                {"Purple", {110, 52, 140}},
                                                {"Cream", {246, 236, 208}}}};

constexpr double kMinShare = 0.10;     // a colour listed covers at least this much
constexpr int kEdgePx = 3;             // mixed with the background at the outline
constexpr int kStepPx = 2;             // every second pixel is plenty for shares
constexpr int kPrintLagPx = 4;         // a print changes colour within a few pixels...
constexpr double kPrintDeltaE = 30.0;  // ...by more than shading across a fold does
constexpr double kPrintFraction = 0.03;
constexpr int kMixLagPx = 1;         // where two colours meet, pixels are a blend of both...
constexpr double kMixDeltaE = 15.0;  // ...and would be named as a third colour (red + white: pink)

cv::Vec3f toLab(const cv::Vec3b& bgr) {
  cv::Mat3f px(1, 1, cv::Vec3f(bgr[0] / 255.0f, bgr[1] / 255.0f, bgr[2] / 255.0f));
  cv::Mat3f lab;
  cv::cvtColor(px, lab, cv::COLOR_BGR2Lab);
  return lab(0, 0);
}

const std::vector<cv::Vec3f>& paletteLab() {
  static const std::vector<cv::Vec3f> kLab = [] {
    std::vector<cv::Vec3f> out;
    for (const auto& p : kPalette)
      out.push_back(toLab(cv::Vec3b(static_cast<uchar>(p.rgb[2]), static_cast<uchar>(p.rgb[1]),
                                    static_cast<uchar>(p.rgb[0]))));
    return out;
  }();
  return kLab;
}

// Nearest palette colour. Lightness counts half: the same cloth is lighter on the lit side of
// the form and darker in a fold, and must keep one name.
int nearestPalette(const cv::Vec3f& lab) {
  const auto& pal = paletteLab();
  int best = 0;
  double bestD = 1e30;
  for (int i = 0; i < static_cast<int>(pal.size()); ++i) {
    const double dl = 0.5 * (lab[0] - pal[i][0]);
    const double da = lab[1] - pal[i][1];
    const double db = lab[2] - pal[i][2];
    const double d = dl * dl + da * da + db * db;
    if (d < bestD) {
      bestD = d;
      best = i;
    }
  }
  return best;
}

double deltaE(const cv::Vec3f& a, const cv::Vec3f& b) {
  const cv::Vec3f d = a - b;
  return std::sqrt(d.dot(d));
}

}  // namespace

std::string GarmentColours::label() const {
  std::string out;
  for (std::size_t i = 0; i < colours.size() && i < 3; ++i)
    out += (i ? "/" : "") + colours[i].name;
  return out;
}

const std::vector<std::string>& colourPaletteNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> out;
    for (const auto& p : kPalette)
      out.emplace_back(p.name);
    return out;
  }();
  return kNames;
}

GarmentColours garmentColours(const cv::Mat& bgr, const cv::Mat& mask) {
  if (bgr.type() != CV_8UC3 || mask.type() != CV_8UC1 || bgr.size() != mask.size())
    throw std::invalid_argument(
        "garment colours: need an 8-bit BGR image and an 8-bit mask of the same size");
  cv::Mat1b inner;
  cv::erode(
      mask, inner,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kEdgePx + 1, 2 * kEdgePx + 1)));
  cv::Mat3f lab;
  bgr.convertTo(lab, CV_32FC3, 1.0 / 255.0);
  cv::cvtColor(lab, lab, cv::COLOR_BGR2Lab);

  std::vector<long> count(kPalette.size(), 0);
  std::vector<cv::Vec3d> sum(kPalette.size(), cv::Vec3d(0, 0, 0));
  long total = 0, named = 0, pairs = 0, sharp = 0;
  for (int y = 0; y < inner.rows; y += kStepPx) {
    const uchar* m = inner.ptr<uchar>(y);
    for (int x = 0; x < inner.cols; x += kStepPx) {
      if (!m[x])
        continue;
      const cv::Vec3f& here = lab(y, x);
      bool mixed = false;
      for (const auto& [dx, dy] : {std::pair{kMixLagPx, 0}, std::pair{-kMixLagPx, 0},
                                   std::pair{0, kMixLagPx}, std::pair{0, -kMixLagPx}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx >= 0 && ny >= 0 && nx < inner.cols && ny < inner.rows && inner(ny, nx) &&
            deltaE(here, lab(ny, nx)) > kMixDeltaE)
          mixed = true;
      }
      ++total;
      if (!mixed) {
        const int k = nearestPalette(here);
        ++count[static_cast<std::size_t>(k)];
        const cv::Vec3b& c = bgr.at<cv::Vec3b>(y, x);
        sum[static_cast<std::size_t>(k)] += cv::Vec3d(c[0], c[1], c[2]);
        ++named;
      }
      for (const auto& [dx, dy] : {std::pair{kPrintLagPx, 0}, std::pair{0, kPrintLagPx}}) {
        if (x + dx >= inner.cols || y + dy >= inner.rows || !inner(y + dy, x + dx))
          continue;
        ++pairs;
        if (deltaE(here, lab(y + dy, x + dx)) > kPrintDeltaE)
          ++sharp;
      }
    }
  }
  if (total * kStepPx * kStepPx < 100)
    throw std::invalid_argument("garment colours: the garment mask has fewer than 100 pixels");

  GarmentColours out;
  for (std::size_t k = 0; k < kPalette.size() && named > 0; ++k) {
    const double share = static_cast<double>(count[k]) / static_cast<double>(named);
    if (share < kMinShare)
      continue;
    const cv::Vec3d mean = sum[k] / static_cast<double>(count[k]);
    out.colours.push_back(
        {kPalette[k].name, share,
         cv::Vec3b(cv::saturate_cast<uchar>(mean[0]), cv::saturate_cast<uchar>(mean[1]),
                   cv::saturate_cast<uchar>(mean[2]))});
  }
  std::sort(out.colours.begin(), out.colours.end(),
            [](const NamedColour& a, const NamedColour& b) { return a.share > b.share; });
  out.printed =
      pairs > 0 && static_cast<double>(sharp) / static_cast<double>(pairs) > kPrintFraction;
  return out;
}

}  // namespace garmcap::daemon
