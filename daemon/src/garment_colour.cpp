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
// Shading: the same cloth lit and in a fold or turned from the light has nearly proportional
// colours (a diffuse surface reflects a share of the light in every channel alike; sRGB's power
// law keeps proportion), so the palette splits one cloth into a lit and a shaded name (Blue and
// Navy, Purple and Navy, Cream and Beige on the physical rig's solids). Two names are one cloth
// when they touch and their mean colours point the same way within this angle and differ in
// brightness by at most this factor (lit and shaded sides of the physical rig's solids differ by
// 1.1-1.4; black beside grey, 3 and more, is two cloths).
constexpr double kShadingMaxAngleDeg = 7.0;
constexpr double kShadingMaxRatio = 1.8;
// The name of one cloth: of its names holding at least this share of its pixels, the most
// saturated (highlights clip towards white, shadows towards black; the cloth's colour is
// between).
constexpr double kClothNameMinShare = 0.15;
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

// One cloth: palette names merged as shading of each other (kShadingMaxAngleDeg).
struct Cloth {
  int name = -1;  // the palette name it is listed by
  long count = 0;
  cv::Vec3d sum{0, 0, 0};  // BGR sum of its pixels
};

double chroma(const cv::Vec3d& meanBgr) {
  const cv::Vec3f lab =
      toLab(cv::Vec3b(cv::saturate_cast<uchar>(meanBgr[0]), cv::saturate_cast<uchar>(meanBgr[1]),
                      cv::saturate_cast<uchar>(meanBgr[2])));
  return std::hypot(lab[1], lab[2]);
}

// Whether mean colours `a` and `b` are one cloth's lit and shaded sides (see kShadingMaxAngleDeg).
bool shadingOfEachOther(const cv::Vec3d& a, const cv::Vec3d& b) {
  const double na = cv::norm(a), nb = cv::norm(b);
  if (na < 1e-6 || nb < 1e-6)
    return false;
  const double cosAngle = std::clamp(a.dot(b) / (na * nb), -1.0, 1.0);
  const double angleDeg = std::acos(cosAngle) * 180.0 / CV_PI;
  return angleDeg <= kShadingMaxAngleDeg && std::max(na, nb) <= kShadingMaxRatio * std::min(na, nb);
}

// The palette names found, merged into cloths: the largest name not yet taken leads a cloth, which
// takes every smaller name that touches one of its names (sampled neighbours) and is its shading;
// each cloth is then listed by its most saturated name among those holding kClothNameMinShare of
// it.
std::vector<Cloth> clothsOf(const std::vector<long>& count, const std::vector<cv::Vec3d>& sum,
                            const cv::Mat1i& nameOf) {
  const std::size_t n = count.size();
  std::vector<std::vector<bool>> touch(n, std::vector<bool>(n, false));
  for (int y = 0; y < nameOf.rows; y += kStepPx)
    for (int x = 0; x < nameOf.cols; x += kStepPx) {
      const int a = nameOf(y, x);
      if (a < 0)
        continue;
      for (const auto& [nx, ny] : {std::pair{x + kStepPx, y}, std::pair{x, y + kStepPx}}) {
        if (nx >= nameOf.cols || ny >= nameOf.rows)
          continue;
        const int b = nameOf(ny, nx);
        if (b >= 0 && b != a)
          touch[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] =
              touch[static_cast<std::size_t>(b)][static_cast<std::size_t>(a)] = true;
      }
    }
  std::vector<std::size_t> bySize;
  for (std::size_t k = 0; k < n; ++k)
    if (count[k] > 0)
      bySize.push_back(k);
  std::sort(bySize.begin(), bySize.end(),
            [&](std::size_t a, std::size_t b) { return count[a] > count[b]; });
  std::vector<bool> taken(n, false);
  std::vector<Cloth> cloths;
  for (std::size_t i = 0; i < bySize.size(); ++i) {
    const std::size_t lead = bySize[i];
    if (taken[lead])
      continue;
    // A name joins when it touches a member and is its shading, and is within the shading
    // range of the lead too (so that no chain of small steps runs from white to black).
    const auto meanOf = [&](std::size_t k) { return sum[k] / static_cast<double>(count[k]); };
    const double leadNorm = cv::norm(meanOf(lead));
    std::vector<std::size_t> members{lead};
    taken[lead] = true;
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t j = i + 1; j < bySize.size(); ++j) {
        const std::size_t k = bySize[j];
        if (taken[k])
          continue;
        const double ratio = cv::norm(meanOf(k)) / std::max(leadNorm, 1e-6);
        if (ratio > kShadingMaxRatio || ratio < 1.0 / kShadingMaxRatio)
          continue;
        for (std::size_t m : members)
          if (touch[m][k] && shadingOfEachOther(meanOf(m), meanOf(k))) {
            members.push_back(k);
            taken[k] = true;
            grew = true;
            break;
          }
      }
    }
    Cloth cloth;
    for (std::size_t k : members) {
      cloth.count += count[k];
      cloth.sum += sum[k];
    }
    double bestChroma = -1;
    for (std::size_t k : members) {
      if (static_cast<double>(count[k]) < kClothNameMinShare * static_cast<double>(cloth.count))
        continue;
      const double c = chroma(sum[k] / static_cast<double>(count[k]));
      if (c > bestChroma) {
        bestChroma = c;
        cloth.name = static_cast<int>(k);
      }
    }
    cloths.push_back(cloth);
  }
  return cloths;
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

cv::Vec3b paletteColourBgr(const std::string& name) {
  for (const auto& p : kPalette)
    if (name == p.name)
      return cv::Vec3b(static_cast<uchar>(p.rgb[2]), static_cast<uchar>(p.rgb[1]),
                       static_cast<uchar>(p.rgb[0]));
  throw std::invalid_argument("no colour named '" + name + "' in the palette");
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
  cv::Mat1i nameOf(inner.size(), -1);  // palette index of each sampled, unmixed pixel
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
        nameOf(y, x) = k;
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
  for (const Cloth& cloth : clothsOf(count, sum, nameOf)) {
    const double share = static_cast<double>(cloth.count) / static_cast<double>(named);
    if (share < kMinShare)
      continue;
    const cv::Vec3d mean = cloth.sum / static_cast<double>(cloth.count);
    out.colours.push_back(
        {kPalette[static_cast<std::size_t>(cloth.name)].name, share,
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
