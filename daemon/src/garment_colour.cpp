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

constexpr double kMinShare = 0.10;  // a colour listed covers at least this much
constexpr int kEdgePx = 3;          // mixed with the background at the outline
constexpr int kStepPx = 2;          // every second pixel is plenty for shares
// Print: the share of the garment whose colour departs from the garment's own dominant colour
// around it. That local colour is the median over a window of about 4-5 cm (a twelfth of the
// garment's size, sqrt of its area: 45-75 cm for the garments a form wears), which follows
// shading and folds (they change over more than a window) but not a dot, a stripe or a check
// line (less than half a window wide, so the median takes the ground's colour). A fold's crease
// or a seam is a thin line: a percent or two of the garment. The outline is left out by about
// 1.3 cm, where spill, the soft alpha and the shadow of the form's edge live.
constexpr double kPrintAnalysisPx = 600;  // sqrt(garment area) is resampled to at most this
constexpr double kPrintWindowFraction = 1.0 / 12;
constexpr double kPrintEdgeFraction = 1.0 / 40;
constexpr double kPrintDeltaE = 12.0;  // a colour change a shopper sees as another colour
constexpr double kPrintShare = 0.05;   // more than this share of the garment is the print
constexpr int kMixLagPx = 1;           // where two colours meet, pixels are a blend of both...
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

// Every pixel outside `mask` takes the colour of the nearest garment pixel, so that a median
// near the outline sees the garment only (not the white or black behind a cut-out).
cv::Mat3b extendOutward(const cv::Mat3b& image, const cv::Mat1b& mask) {
  cv::Mat dist, labels;
  // Zero pixels of the source (the garment) are the seeds; each gets its own label.
  cv::distanceTransform(mask == 0, dist, labels, cv::DIST_L2, 5, cv::DIST_LABEL_PIXEL);
  double maxLabel = 0;
  cv::minMaxLoc(labels, nullptr, &maxLabel);
  std::vector<cv::Vec3b> colourOf(static_cast<std::size_t>(maxLabel) + 1, cv::Vec3b(0, 0, 0));
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask(y, x))
        colourOf[static_cast<std::size_t>(labels.at<int>(y, x))] = image(y, x);
  cv::Mat3b out(image.size());
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      out(y, x) =
          mask(y, x) ? image(y, x) : colourOf[static_cast<std::size_t>(labels.at<int>(y, x))];
  return out;
}

// The share of the garment's inner pixels more than kPrintDeltaE from the median colour of the
// window around them (see kPrintWindowFraction). 0 for a garment too thin to have an inside.
double printShare(const cv::Mat& bgr, const cv::Mat& mask) {
  const cv::Rect box = cv::boundingRect(mask);
  cv::Mat3b image = bgr(box).clone();
  cv::Mat1b garment = mask(box) != 0;
  double sidePx = std::sqrt(static_cast<double>(cv::countNonZero(garment)));
  // A 12 MP cut-out is analysed at about 10 px/cm: motifs keep several pixels, the work stays
  // small.
  if (sidePx > kPrintAnalysisPx) {
    const double f = kPrintAnalysisPx / sidePx;
    cv::resize(image, image, cv::Size(), f, f, cv::INTER_AREA);
    cv::Mat1b scaled;
    cv::resize(garment, scaled, image.size(), 0, 0, cv::INTER_AREA);
    garment = scaled > 127;
    sidePx = std::sqrt(static_cast<double>(cv::countNonZero(garment)));
  }
  const int window = std::max(5, static_cast<int>(sidePx * kPrintWindowFraction) | 1);
  const int edge = std::max(kEdgePx, static_cast<int>(std::lround(sidePx * kPrintEdgeFraction)));
  cv::Mat1b inner;
  cv::erode(garment, inner,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * edge + 1, 2 * edge + 1)));
  const int innerCount = cv::countNonZero(inner);
  if (innerCount == 0)
    return 0;
  cv::Mat3b lab;  // 8-bit Lab: L * 255 / 100, a + 128, b + 128
  cv::cvtColor(image, lab, cv::COLOR_BGR2Lab);
  cv::Mat3b local;
  cv::medianBlur(extendOutward(lab, garment), local, window);
  long departing = 0;
  for (int y = 0; y < inner.rows; ++y)
    for (int x = 0; x < inner.cols; ++x) {
      if (!inner(y, x))
        continue;
      const cv::Vec3b& p = lab(y, x);
      const cv::Vec3b& q = local(y, x);
      const double dl = (p[0] - q[0]) * (100.0 / 255.0);
      const double da = p[1] - q[1], db = p[2] - q[2];
      if (dl * dl + da * da + db * db > kPrintDeltaE * kPrintDeltaE)
        ++departing;
    }
  return static_cast<double>(departing) / innerCount;
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
  long total = 0, named = 0;
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
  out.printShare = printShare(bgr, mask);
  out.printed = out.printShare > kPrintShare;
  return out;
}

std::optional<GarmentColours> captureColours(const pipeline::CaptureResult& capture,
                                             const cv::Mat& dressedBgr) {
  if (!capture.cutout.empty() && capture.cutout.type() == CV_8UC4) {
    cv::Mat bgr, alpha;
    cv::cvtColor(capture.cutout, bgr, cv::COLOR_BGRA2BGR);
    cv::extractChannel(capture.cutout, alpha, 3);
    return garmentColours(bgr, alpha > 200);
  }
  if (!capture.silhouette.empty() && dressedBgr.type() == CV_8UC3 &&
      capture.silhouette.size() == dressedBgr.size())
    return garmentColours(dressedBgr, capture.silhouette);
  return std::nullopt;
}

}  // namespace garmcap::daemon
