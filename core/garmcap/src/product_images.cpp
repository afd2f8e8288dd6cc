#include "garmcap/pipeline/product_images.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace garmcap::pipeline {
namespace {

// Band widths along the outline, in cm of the garment (scaled by the frame's px per cm).
constexpr double kGuideRadiusCm = 0.12;  // guided filter: about the lens blur plus a mixed pixel
constexpr double kGuideEps = 1e-3;       // guided filter regulariser (grey levels 0..1)
constexpr double kFormBandCm = 1.0;      // how deep a remain of the form can reach into the mask
constexpr double kFormDeltaE = 5.0;      // CIELAB difference below which a pixel is the bare frame
constexpr double kMaxUpscale = 1.5;      // at most this much up to minSidePx: beyond, the photo
                                         // would show interpolation, not fabric
constexpr double kSpillBandCm = 2.5;     // green spill fades within ~1 cm of an edge; 2.5 cm is
                                         // where a studio's spill is down to a few percent

// The drop shadow, in fractions of the garment's height (so it looks the same at any zoom and
// any garment size) and its opacity. The outline is shrunk by 3.5 sigma, where the blur's tail
// is under half a grey level, so nothing shows beside the garment or above it (the margins stay
// pure white), and moved down by 1.5 % more than that: under the hem the shadow's own edge lies
// 1 sigma below it, and its tail is white again 3.5 sigma further, inside the 6 % bottom margin.
constexpr double kShadowSigma = 0.015;  // blur: a soft studio light, no hard edge to read as dirt
constexpr double kShadowShrink = 3.5 * kShadowSigma;
constexpr double kShadowDrop = kShadowShrink + kShadowSigma;
constexpr double kShadowOpacity = 0.2;  // darkest: white to 204 grey; just under a straight hem
                                        // about 0.17 (212): seen, not a dark band

// CIELAB (L 0..100, a and b in their units) through OpenCV's 8-bit conversion: its tables make
// it about ten times faster than the float one on a 12 MP garment's crop, and its steps (0.4 L,
// 1 a* or b*) are well below the thresholds used here. The 8-bit values go to float through a
// table in one pass (convertTo, then multiply and subtract, were three passes over a float image
// of the crop's size); each value is the same float those made: v * float(100 / 255) for L,
// v - 128 for a and b.
cv::Mat3f labOf(const cv::Mat3b& bgr) {
  static const std::array<std::array<float, 256>, 2> toLab = [] {
    std::array<std::array<float, 256>, 2> t{};
    for (int v = 0; v < 256; ++v) {
      t[0][static_cast<std::size_t>(v)] =
          static_cast<float>(v) * static_cast<float>(100.0 / 255.0) - 0.0f;
      t[1][static_cast<std::size_t>(v)] = static_cast<float>(v) * 1.0f - 128.0f;
    }
    return t;
  }();
  cv::Mat3b lab8;
  cv::cvtColor(bgr, lab8, cv::COLOR_BGR2Lab);
  cv::Mat3f lab(lab8.size());
  for (int y = 0; y < lab8.rows; ++y) {
    const cv::Vec3b* in = lab8.ptr<cv::Vec3b>(y);
    cv::Vec3f* out = lab.ptr<cv::Vec3f>(y);
    for (int x = 0; x < lab8.cols; ++x)
      out[x] = cv::Vec3f(toLab[0][in[x][0]], toLab[1][in[x][1]], toLab[1][in[x][2]]);
  }
  return lab;
}

// labOf's inverse, in one pass: (L + 0) * float(255 / 100) and a + 128, b + 128, rounded as
// convertTo rounds.
cv::Mat3b bgrOf(const cv::Mat3f& lab) {
  const float kL = static_cast<float>(255.0 / 100.0);
  cv::Mat3b lab8(lab.size());
  for (int y = 0; y < lab.rows; ++y) {
    const cv::Vec3f* in = lab.ptr<cv::Vec3f>(y);
    cv::Vec3b* out = lab8.ptr<cv::Vec3b>(y);
    for (int x = 0; x < lab.cols; ++x)
      out[x] = cv::Vec3b(cv::saturate_cast<uchar>((in[x][0] + 0.0f) * kL),
                         cv::saturate_cast<uchar>((in[x][1] + 128.0f) * 1.0f),
                         cv::saturate_cast<uchar>((in[x][2] + 128.0f) * 1.0f));
  }
  cv::Mat3b bgr;
  cv::cvtColor(lab8, bgr, cv::COLOR_Lab2BGR);
  return bgr;
}

// The CIELAB distance of two images pixel by pixel, in one pass (a difference, three products and
// two sums were a float image each): the same float operations in the same order.
inline float labDist(const cv::Vec3f& a, const cv::Vec3f& b) {
  const float d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  const float sq01 = d0 * d0 + d1 * d1;
  return std::sqrt(sq01 + d2 * d2);
}

cv::Mat1f labDistance(const cv::Mat3f& p, const cv::Mat3f& q) {
  cv::Mat1f out(p.size());
  for (int y = 0; y < p.rows; ++y) {
    const cv::Vec3f* a = p.ptr<cv::Vec3f>(y);
    const cv::Vec3f* b = q.ptr<cv::Vec3f>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < p.cols; ++x)
      o[x] = labDist(a[x], b[x]);
  }
  return out;
}

// Distance (px) of each pixel of `inside` to the nearest pixel outside it.
cv::Mat1f depthInside(const cv::Mat1b& inside) {
  cv::Mat1f d;
  cv::distanceTransform(inside, d, cv::DIST_L2, cv::DIST_MASK_3);
  return d;
}

cv::Mat1f boxMean(const cv::Mat1f& m, int r) {
  cv::Mat1f out;
  cv::boxFilter(m, out, CV_32F, cv::Size(2 * r + 1, 2 * r + 1), cv::Point(-1, -1), true,
                cv::BORDER_REFLECT);
  return out;
}

// Gaussian average of `value` weighted by `weight`, at reduced resolution (sigmas of tens of
// pixels at full resolution): value and weight sums, each blurred, back at full size.
void weightedBlur(const std::vector<cv::Mat1f>& values, const cv::Mat1f& weight, double sigmaPx,
                  std::vector<cv::Mat1f>& sums, cv::Mat1f& weightSum) {
  const double f = std::max(1.0, sigmaPx / 3.0);
  const cv::Size small(std::max(1, static_cast<int>(std::lround(weight.cols / f))),
                       std::max(1, static_cast<int>(std::lround(weight.rows / f))));
  auto blurred = [&](const cv::Mat1f& m) {
    cv::Mat1f s, b, out;
    cv::resize(m, s, small, 0, 0, cv::INTER_AREA);
    cv::GaussianBlur(s, b, cv::Size(), sigmaPx / f);
    cv::resize(b, out, weight.size(), 0, 0, cv::INTER_LINEAR);
    return out;
  };
  weightSum = blurred(weight);
  sums.clear();
  for (const auto& v : values)
    sums.push_back(blurred(v.mul(weight)));
}

// A partly covered edge pixel mixes the garment with what is behind it, and behind it is what
// the registered bare frame shows there (screen or form): its garment colour is
// (c - (1 - alpha) bare) / alpha. Pixels under a quarter covered are left: the division would
// amplify noise and they hardly show on white.
void unmixEdge(cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Mat3b& bare) {
  for (int y = 0; y < bgr.rows; ++y) {
    const float* a = alpha.ptr<float>(y);
    const cv::Vec3b* b = bare.ptr<cv::Vec3b>(y);
    cv::Vec3b* p = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      if (a[x] < 0.25f || a[x] >= 1.0f)
        continue;
      for (int c = 0; c < 3; ++c)
        p[x][c] = cv::saturate_cast<uchar>((p[x][c] - (1.0f - a[x]) * b[x][c]) / a[x]);
    }
  }
}

}  // namespace

namespace {

// The drop shadow at reduced resolution (a third of the blur's sigma a pixel, as weightedBlur):
// the shadow has no detail finer than that. The garment's alpha `boxAlpha` lies at `offset` on a
// canvas of `canvas` size; only its box is scaled down (straight onto the small canvas, at its
// exact sub-pixel place), so no canvas-sized float image is made: at 12 MP those full-size passes
// (a float canvas, its copy, the float shadow scaled back up, 255 (1 - shadow)) were nine tenths of
// the shadow's cost (tests/bench/product_photo_bench, third table).
struct SmallShadow {
  cv::Mat1f darkness;  // 0..kShadowOpacity on the small canvas
};

SmallShadow smallShadow(const cv::Mat1f& boxAlpha, cv::Point offset, cv::Size canvas) {
  const double h = boxAlpha.rows;
  const double sigma = std::max(1.0, kShadowSigma * h);
  const double f = std::max(1.0, sigma / 3.0);
  const cv::Size small(std::max(1, static_cast<int>(std::lround(canvas.width / f))),
                       std::max(1, static_cast<int>(std::lround(canvas.height / f))));
  const cv::Size smallBox(std::max(1, static_cast<int>(std::lround(boxAlpha.cols / f))),
                          std::max(1, static_cast<int>(std::lround(boxAlpha.rows / f))));
  cv::Mat1f boxSmall;
  cv::resize(boxAlpha, boxSmall, smallBox, 0, 0, cv::INTER_AREA);
  // Small-box pixel u (centre at u + 0.5 in edge coordinates) lies at canvas edge coordinate
  // offset + (u + 0.5) w / w', that is small-canvas centre coordinate
  // (offset + (u + 0.5) w / w') / f - 0.5.
  const double kx = static_cast<double>(boxAlpha.cols) / smallBox.width / f;
  const double ky = static_cast<double>(boxAlpha.rows) / smallBox.height / f;
  const cv::Matx23d toCanvas(kx, 0.0, offset.x / f + 0.5 * kx - 0.5, 0.0, ky,
                             offset.y / f + 0.5 * ky - 0.5);
  cv::Mat1f a;
  cv::warpAffine(boxSmall, a, toCanvas, small, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
  // Shrunk from the half-covered outline (the soft edge's middle) by a distance transform: one
  // pass, where an erosion would cost a kernel that wide.
  const cv::Mat1b solid = a >= 0.5f;
  const cv::Mat1f depth = depthInside(solid);
  const cv::Mat1b core = depth > static_cast<float>(kShadowShrink * h / f);
  const int drop = static_cast<int>(std::lround(kShadowDrop * h / f));
  cv::Mat1f moved = cv::Mat1f::zeros(small);
  if (drop < moved.rows) {
    const cv::Rect from(0, 0, moved.cols, moved.rows - drop);
    core(from).convertTo(moved(from + cv::Point(0, drop)), CV_32F, kShadowOpacity / 255.0);
  }
  // Beyond the canvas is white (no shadow), hence the zero border.
  SmallShadow out;
  cv::GaussianBlur(moved, out.darkness, cv::Size(), sigma / f, sigma / f, cv::BORDER_CONSTANT);
  return out;
}

// The white background with the shadow, 8-bit grey at the canvas's size: scaled up from the
// small canvas in 8 bits (within a grey level of scaling the float darkness up and rounding).
cv::Mat1b shadowedWhite(const cv::Mat1f& boxAlpha, cv::Point offset, cv::Size canvas) {
  const SmallShadow s = smallShadow(boxAlpha, offset, canvas);
  cv::Mat1b smallGrey, grey;
  s.darkness.convertTo(smallGrey, CV_8U, -255.0, 255.0);
  cv::resize(smallGrey, grey, canvas, 0, 0, cv::INTER_LINEAR);
  return grey;
}

}  // namespace

cv::Mat1f dropShadow(const cv::Mat1f& canvasAlpha) {
  cv::Mat1f shadow = cv::Mat1f::zeros(canvasAlpha.size());
  const cv::Rect box = cv::boundingRect(canvasAlpha > 0.0f);
  if (box.area() == 0)
    return shadow;
  const SmallShadow s = smallShadow(canvasAlpha(box), box.tl(), canvasAlpha.size());
  cv::resize(s.darkness, shadow, canvasAlpha.size(), 0, 0, cv::INTER_LINEAR);
  return shadow;
}

cv::Mat makeCutout(const cv::Mat& bgr, const cv::Mat& mask, double featherPx) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("cutout: frame must be an 8-bit BGR image");
  if (mask.size() != bgr.size() || mask.type() != CV_8UC1)
    throw std::invalid_argument("cutout: mask must be CV_8UC1 of the frame's size");
  // A hard mask edge shows stair steps on the white background; a short ramp centred on the
  // boundary hides them without eating into the garment.
  cv::Mat alpha;
  cv::threshold(mask, alpha, 0, 255, cv::THRESH_BINARY);
  if (featherPx > 0) {
    const int k = 2 * static_cast<int>(std::ceil(2 * featherPx)) + 1;
    cv::GaussianBlur(alpha, alpha, cv::Size(k, k), featherPx);
  }
  cv::Mat bgra;
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  cv::Mat channels[4];
  cv::split(bgra, channels);
  channels[3] = alpha;
  cv::merge(channels, 4, bgra);
  return bgra;
}

cv::Mat1f refinedAlpha(const cv::Mat3b& bgr, const cv::Mat1b& mask, int radiusPx) {
  if (mask.size() != bgr.size())
    throw std::invalid_argument("refinedAlpha: the mask is not the frame's size");
  cv::Mat1f alpha;
  const cv::Mat1b binary = mask > 0;
  binary.convertTo(alpha, CV_32F, 1.0 / 255.0);
  if (radiusPx < 1 || cv::countNonZero(mask) == 0)
    return alpha;
  // Guided filter (He, Sun and Tang): locally, alpha is a linear function of the grey level, so
  // the ramp sits on the garment's own edge in the frame instead of on the mask's steps.
  cv::Mat1b grey8;
  cv::cvtColor(bgr, grey8, cv::COLOR_BGR2GRAY);
  cv::Mat1f I;
  grey8.convertTo(I, CV_32F, 1.0 / 255.0);
  const int r = radiusPx;
  // The element-wise steps each in one pass over the crop (as matrix expressions they made a
  // float image per product, difference and quotient): the same float operations in the same
  // order, so the same alpha.
  const auto eachPixel = [&I](auto&& f) {
    for (int y = 0; y < I.rows; ++y)
      for (int x = 0; x < I.cols; ++x)
        f(y, x);
  };
  cv::Mat1f II(I.size()), IP(I.size());
  eachPixel([&](int y, int x) {
    const float i = I(y, x);
    II(y, x) = i * i;
    IP(y, x) = i * alpha(y, x);
  });
  const cv::Mat1f meanI = boxMean(I, r), meanP = boxMean(alpha, r);
  const cv::Mat1f meanII = boxMean(II, r), meanIP = boxMean(IP, r);
  cv::Mat1f a(I.size()), b(I.size());
  const float eps = static_cast<float>(kGuideEps);
  eachPixel([&](int y, int x) {
    const float mI = meanI(y, x), mP = meanP(y, x);
    const float varI = meanII(y, x) - mI * mI;
    const float covIP = meanIP(y, x) - mI * mP;
    const float ay = covIP / (varI + eps);
    a(y, x) = ay;
    b(y, x) = mP - ay * mI;
  });
  const cv::Mat1f meanA = boxMean(a, r), meanB = boxMean(b, r);
  cv::Mat1f q(I.size());
  eachPixel([&](int y, int x) {
    const float v = meanA(y, x) * I(y, x) + meanB(y, x);
    q(y, x) = std::min(std::max(v, 0.0f), 1.0f);
  });
  // Only the outline's band takes the filter's answer: deep inside and far outside the mask
  // stays as segmentation decided (a print's contrast must not open holes).
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  cv::Mat1b grown, shrunk;
  cv::dilate(mask, grown, k);
  cv::erode(mask, shrunk, k);
  q.copyTo(alpha, grown & ~shrunk);
  return alpha;
}

namespace {

// formRemains, with `nearPx` >= 0: the per-pixel test only inside the band and outside the mask
// within `nearPx` (square) of it, elsewhere no candidate. The cut is then the same as the whole
// crop's within nearPx - 2 of the mask (the closing looks 2 px away): an outside candidate is cut
// whatever its component, and a band component that reaches the outside does so first through
// an outside pixel next to the mask. Farther out the alpha is 0 and the cut does not matter.
cv::Mat1b formRemainsNear(const cv::Mat3b& dressed, const cv::Mat3b& bare, const cv::Mat1b& mask,
                          double bandPx, double maxDeltaE,
                          const std::optional<cv::Vec3b>& screenBgr, int nearPx) {
  if (bare.size() != dressed.size() || mask.size() != dressed.size())
    throw std::invalid_argument("formRemains: the frames and the mask differ in size");
  // A light blur against sensor noise; a wider one would spread a dark hem's contrast onto the
  // form below it, and the remain right under the hem would no longer look like the bare frame.
  cv::Mat3b d, e;
  cv::GaussianBlur(dressed, d, cv::Size(3, 3), 0.8);
  cv::GaussianBlur(bare, e, cv::Size(3, 3), 0.8);
  const cv::Mat3f labD = labOf(d);
  const cv::Mat1f depth = depthInside(mask);
  const cv::Mat1b band = (depth <= static_cast<float>(bandPx)) & mask;
  // The garment's own look near each band pixel: the colour of the mask a few px in from its
  // outline, averaged along it. A pixel much closer to the bare frame than to that is form or
  // screen even where noise keeps it a few units from the bare frame (a mixed pixel counts with
  // the side it is closer to); only when it is clearly unlike the garment (twice the sameness
  // threshold), or noise would shave the hem of a garment close to the form's colour.
  cv::Mat1f core;
  const cv::Mat1b coreMask = depth > static_cast<float>(std::max(3.0, 0.25 * bandPx));
  coreMask.convertTo(core, CV_32F, 1.0 / 255.0);
  std::vector<cv::Mat1f> ch;
  cv::split(labD, ch);
  std::vector<cv::Mat1f> sums;
  cv::Mat1f wsum;
  weightedBlur(ch, core, std::max(2.0, 0.5 * bandPx), sums, wsum);
  cv::Mat1f garmentLook[3];
  for (int c = 0; c < 3; ++c)
    garmentLook[c] = sums[c] / cv::max(wsum, 1e-6f);
  cv::Mat3f look;
  cv::merge(garmentLook, 3, look);
  const float t = static_cast<float>(maxDeltaE);
  const cv::Vec3f screenLab =
      screenBgr ? labOf(cv::Mat3b(1, 1, *screenBgr))(0, 0) : cv::Vec3f(0.f, 0.f, 0.f);
  // The spill test of one pixel (below, where the whole crop is tested).
  const auto spilledForm = [&](const cv::Vec3f& lD, const cv::Vec3f& lE, const cv::Vec3f& lk) {
    cv::Vec3f diff = lD - lE;
    const cv::Vec3f toScreen = screenLab - lE;
    const float s2 = toScreen.dot(toScreen);
    if (s2 > 1e-6f) {
      const float k = diff.dot(toScreen) / s2;
      if (k > 0)
        diff -= k * toScreen;
    }
    const cv::Vec3f toGarment = lk - lE;
    const float len = std::sqrt(toGarment.dot(toGarment));
    const float towards = len > 1e-3f ? diff.dot(toGarment) / len : 0.0f;
    return std::sqrt(diff.dot(diff)) < t && towards < 0.5f * t;
  };
  const cv::Mat1b outside = mask == 0;
  cv::Mat1b candidate;
  if (nearPx >= 0) {
    cv::Mat1b grown;
    cv::dilate(mask, grown, cv::Mat(), cv::Point(-1, -1), nearPx);
    const cv::Mat1b work = band | (outside & (grown > 0));
    candidate = cv::Mat1b::zeros(mask.size());
    // Tiles, so that the Lab conversions skip the garment's inside and the far outside.
    constexpr int kTile = 64;
    const cv::Rect frame(0, 0, mask.cols, mask.rows);
    for (int ty = 0; ty < mask.rows; ty += kTile)
      for (int tx = 0; tx < mask.cols; tx += kTile) {
        const cv::Rect r = cv::Rect(tx, ty, kTile, kTile) & frame;
        if (cv::countNonZero(work(r)) == 0)
          continue;
        const cv::Mat3f lRaw = labOf(dressed(r)), lBareRaw = labOf(bare(r)), lE = labOf(e(r));
        for (int y = 0; y < r.height; ++y) {
          const uchar* wk = work.ptr(r.y + y) + r.x;
          const cv::Vec3f* lD = labD.ptr<cv::Vec3f>(r.y + y) + r.x;
          const cv::Vec3f* lk = look.ptr<cv::Vec3f>(r.y + y) + r.x;
          const float* ws = wsum.ptr<float>(r.y + y) + r.x;
          uchar* out = candidate.ptr(r.y + y) + r.x;
          for (int x = 0; x < r.width; ++x) {
            if (!wk[x])
              continue;
            const float dB = labDist(lD[x], lE(y, x));
            const float dGB = labDist(lD[x], lk[x]);
            const float dG = labDist(lRaw(y, x), lk[x]);
            const float dBR = labDist(lRaw(y, x), lBareRaw(y, x));
            const bool formSide = screenBgr && dB < 2 * t && dB >= t && dB < dGB && ws[x] > 0.02f &&
                                  spilledForm(lD[x], lE(y, x), lk[x]);
            const bool nearBare = (dB < t && (dB < dGB || ws[x] <= 0.02f)) || formSide;
            const bool same =
                nearBare ||
                (dBR < 0.5f * dG && dG > 2.0f * static_cast<float>(maxDeltaE) && ws[x] > 0.02f);
            if (same)
              out[x] = 255;
          }
        }
      }
  } else {
    const cv::Mat3f labE = labOf(e);
    const auto distance = labDistance;
    const cv::Mat1f dBare = distance(labD, labE);
    // Unblurred for this test: a two- or three-pixel sliver of form between a dark leg and the
    // screen is closer to the bare frame than to the garment pixel by pixel, not after a blur.
    const cv::Mat3f labRaw = labOf(dressed);
    const cv::Mat1f dGarment = distance(labRaw, look);
    const cv::Mat1f dBareRaw = distance(labRaw, labOf(bare));
    // Near the bare frame counts only when nearer to it than to the garment: a fabric a shade off
    // the form's colour is within the threshold of the bare frame at its edge too.
    const cv::Mat1f dGarmentBlurred = distance(labD, look);
    // Spill: the screen's light tints the form beside the garment in the dressed frame only (the
    // form at the crotch, between a leg and the screen, reads 6-9 units off its bare self, greener,
    // and less than 1 unit towards the pants' look). Such a pixel is form when, its shift towards
    // the screen's colour taken out, it is within the threshold of the bare frame and moved less
    // than half the threshold towards the garment (a mixed edge pixel moves along that direction).
    // A print's light square near the form's colour is not tinted towards the screen, so it stays.
    cv::Mat1b formSide = cv::Mat1b::zeros(dressed.size());
    if (screenBgr) {
      for (int y = 0; y < dressed.rows; ++y)
        for (int x = 0; x < dressed.cols; ++x) {
          const float db = dBare(y, x);
          if (!(db < 2 * t && db >= t && db < dGarmentBlurred(y, x) && wsum(y, x) > 0.02f))
            continue;
          if (spilledForm(labD(y, x), labE(y, x), look(y, x)))
            formSide(y, x) = 255;
        }
    }
    const cv::Mat1b nearBare =
        ((dBare < t) & ((dBare < dGarmentBlurred) | (wsum <= 0.02f))) | formSide;
    const cv::Mat1b same =
        nearBare | ((dBareRaw < 0.5f * dGarment) &
                    (dGarment > 2.0f * static_cast<float>(maxDeltaE)) & (wsum > 0.02f));
    candidate = same & (band | outside);
  }
  cv::Mat1i labels;
  const int n = cv::connectedComponents(candidate, labels, 8, CV_32S);
  // A component is a remain when it reaches the outside of the mask: the bare frame's look
  // running in from the form or the screen. One wholly inside the band is the garment's own
  // (a fabric the colour of the form, lit as the form was).
  std::vector<uchar> reaches(static_cast<std::size_t>(n), 0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const uchar* o = outside.ptr(y);
    for (int x = 0; x < labels.cols; ++x)
      if (o[x] && l[x] > 0)
        reaches[static_cast<std::size_t>(l[x])] = 1;
  }
  cv::Mat1b cut = cv::Mat1b::zeros(mask.size());
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    uchar* c = cut.ptr(y);
    for (int x = 0; x < labels.cols; ++x)
      if (l[x] > 0 && reaches[static_cast<std::size_t>(l[x])])
        c[x] = 255;
  }
  // Noise leaves single pixels of a remain a few units too far from the bare frame; enclosed by
  // the cut, they are closed into it (never deeper than the band).
  cv::Mat1b closed;
  cv::morphologyEx(cut, closed, cv::MORPH_CLOSE, cv::Mat());
  cut |= closed & (band | outside);
  return cut;
}

}  // namespace

cv::Mat1b formRemains(const cv::Mat3b& dressed, const cv::Mat3b& bare, const cv::Mat1b& mask,
                      double bandPx, double maxDeltaE, const std::optional<cv::Vec3b>& screenBgr) {
  return formRemainsNear(dressed, bare, mask, bandPx, maxDeltaE, screenBgr, -1);
}

namespace {

// despillEdge; with `nearOnly`, the Lab conversions only where they are read: the band and the
// ring just deeper (tiles that hold any of them), and back to BGR only the changed pixels. The
// conversions are per pixel, so the answer is the same; outside the ring the blur's weight is 0,
// and only the sign of a zero there can differ. The whole inside's chroma (the fallback) is
// taken only when a band pixel needs it, as before from the whole crop.
void despillEdgeImpl(cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Vec3b& screenBgr,
                     double bandPx, bool nearOnly) {
  if (alpha.size() != bgr.size())
    throw std::invalid_argument("despillEdge: the alpha is not the frame's size");
  const cv::Mat1b covered = alpha > 0.0f;
  if (cv::countNonZero(covered) == 0 || bandPx <= 0)
    return;
  const cv::Mat1f depth = depthInside(covered);
  std::vector<cv::Mat1f> ch;
  if (!nearOnly) {
    cv::split(labOf(bgr), ch);
  } else {
    ch = {cv::Mat1f(bgr.size()), cv::Mat1f::zeros(bgr.size()), cv::Mat1f::zeros(bgr.size())};
    const cv::Mat1b used = (depth > 0.f) & (depth <= static_cast<float>(2.0 * bandPx));
    constexpr int kTile = 64;
    const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
    for (int ty = 0; ty < bgr.rows; ty += kTile)
      for (int tx = 0; tx < bgr.cols; tx += kTile) {
        const cv::Rect r = cv::Rect(tx, ty, kTile, kTile) & frame;
        if (cv::countNonZero(used(r)) == 0)
          continue;
        const cv::Mat3f l = labOf(bgr(r));
        for (int y = 0; y < r.height; ++y) {
          const cv::Vec3f* in = l.ptr<cv::Vec3f>(y);
          float* c0 = ch[0].ptr<float>(r.y + y) + r.x;
          float* c1 = ch[1].ptr<float>(r.y + y) + r.x;
          float* c2 = ch[2].ptr<float>(r.y + y) + r.x;
          for (int x = 0; x < r.width; ++x) {
            c0[x] = in[x][0];
            c1[x] = in[x][1];
            c2[x] = in[x][2];
          }
        }
      }
  }
  // The garment's inside chroma near each edge pixel: a wide blur of the chroma of the ring just
  // deeper than the band. Parts too narrow to have a ring (a strap) take the whole inside's.
  const cv::Mat1b ring =
      (depth > static_cast<float>(bandPx)) & (depth <= static_cast<float>(2.0 * bandPx));
  const cv::Mat1b deep = depth > static_cast<float>(bandPx);
  cv::Mat1f w;
  ring.convertTo(w, CV_32F, 1.0 / 255.0);
  std::vector<cv::Mat1f> sums;
  cv::Mat1f wsum;
  weightedBlur({ch[1], ch[2]}, w, 1.5 * bandPx, sums, wsum);
  bool fallbackRead = !nearOnly;
  for (int y = 0; y < bgr.rows && !fallbackRead; ++y) {
    const float* dp = depth.ptr<float>(y);
    const float* wsp = wsum.ptr<float>(y);
    for (int x = 0; x < bgr.cols; ++x)
      if (dp[x] > 0.f && dp[x] <= static_cast<float>(bandPx) && !(wsp[x] > 0.02f)) {
        fallbackRead = true;
        break;
      }
  }
  cv::Vec2f fallback(0.f, 0.f);
  if (fallbackRead && cv::countNonZero(deep) > 0) {
    std::vector<cv::Mat1f> all;
    if (nearOnly)
      cv::split(labOf(bgr), all);
    const std::vector<cv::Mat1f>& c = nearOnly ? all : ch;
    fallback = cv::Vec2f(static_cast<float>(cv::mean(c[1], deep)[0]),
                         static_cast<float>(cv::mean(c[2], deep)[0]));
  }
  // (No inside at all: nothing to compare with but the screen; neutral is the safe guess.)
  cv::Mat3b screenPx(1, 1, screenBgr);
  const cv::Vec3f screenLab = labOf(screenPx)(0, 0);
  const cv::Vec2f screenAB(screenLab[1], screenLab[2]);

  std::vector<cv::Point> at;
  std::vector<cv::Vec3f> moved;
  for (int y = 0; y < bgr.rows; ++y) {
    const float* dp = depth.ptr<float>(y);
    const float* wsp = wsum.ptr<float>(y);
    const float* sa = sums[0].ptr<float>(y);
    const float* sb = sums[1].ptr<float>(y);
    const float* c0 = ch[0].ptr<float>(y);
    const float* c1 = ch[1].ptr<float>(y);
    const float* c2 = ch[2].ptr<float>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      if (dp[x] <= 0.f || dp[x] > static_cast<float>(bandPx))
        continue;
      const cv::Vec2f ref = wsp[x] > 0.02f ? cv::Vec2f(sa[x] / wsp[x], sb[x] / wsp[x]) : fallback;
      cv::Vec2f u = screenAB - ref;
      const float len = std::hypot(u[0], u[1]);
      if (len < 1e-3f)
        continue;
      u /= len;
      const cv::Vec2f p(c1[x], c2[x]);
      const float t = (p - ref).dot(u);
      if (t <= 0.f)
        continue;
      at.emplace_back(x, y);
      moved.emplace_back(c0[x], c1[x] - t * u[0], c2[x] - t * u[1]);
    }
  }
  if (moved.empty())
    return;
  // Back to BGR, only the changed pixels (one row of them).
  const cv::Mat3b back = bgrOf(cv::Mat3f(1, static_cast<int>(moved.size()), moved.data()));
  for (std::size_t i = 0; i < at.size(); ++i)
    bgr(at[i]) = back(0, static_cast<int>(i));
}

}  // namespace

void despillEdge(cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Vec3b& screenBgr,
                 double bandPx) {
  despillEdgeImpl(bgr, alpha, screenBgr, bandPx, false);
}

namespace {

// The garment's box centred on a white canvas of `size` (scaled so that the box fits with the
// margin), composited through alpha; with `shadow`, over its drop shadow. The shadow only darkens
// the background: a fully covered garment pixel is its own colour either way, and a soft edge
// pixel mixes with the shadowed white as it would with a real one.
cv::Mat3b onWhite(const cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Rect& box,
                  cv::Size canvas, bool shadow) {
  const cv::Point offset((canvas.width - box.width) / 2, (canvas.height - box.height) / 2);
  cv::Mat3b out;
  cv::Mat1b background;  // 0..255 per pixel; empty: white everywhere (as before the option)
  if (shadow) {
    background = shadowedWhite(alpha(box), offset, canvas);
    cv::cvtColor(background, out, cv::COLOR_GRAY2BGR);
  } else {
    out.create(canvas);
    out.setTo(cv::Scalar::all(255));
  }
  for (int y = 0; y < box.height; ++y) {
    const cv::Vec3b* src = bgr.ptr<cv::Vec3b>(box.y + y) + box.x;
    const float* a = alpha.ptr<float>(box.y + y) + box.x;
    const uchar* bg = background.empty() ? nullptr : background.ptr(offset.y + y) + offset.x;
    cv::Vec3b* dst = out.ptr<cv::Vec3b>(offset.y + y) + offset.x;
    for (int x = 0; x < box.width; ++x) {
      const float al = a[x];
      if (al <= 0.f)
        continue;
      const float under = bg ? static_cast<float>(bg[x]) : 255.f;
      for (int c = 0; c < 3; ++c)
        dst[x][c] = cv::saturate_cast<uchar>(src[x][c] * al + under * (1.f - al));
    }
  }
  return out;
}

cv::Mat3b sized(const cv::Mat3b& img, int minSidePx, int maxSidePx) {
  const int side = std::max(img.cols, img.rows);
  double f = 1.0;
  if (maxSidePx > 0 && side > maxSidePx)
    f = static_cast<double>(maxSidePx) / side;
  else if (minSidePx > 0 && side < minSidePx)
    f = std::min(static_cast<double>(minSidePx) / side, kMaxUpscale);
  if (f == 1.0)
    return img;
  cv::Mat3b out;
  cv::resize(img, out,
             cv::Size(std::max(1, static_cast<int>(std::lround(img.cols * f))),
                      std::max(1, static_cast<int>(std::lround(img.rows * f)))),
             0, 0, f < 1.0 ? cv::INTER_AREA : cv::INTER_CUBIC);
  return out;
}

}  // namespace

ProductImages makeProductImages(const cv::Mat3b& bgr, const cv::Mat1f& alpha,
                                const ProductImageOptions& options) {
  if (bgr.empty() || alpha.size() != bgr.size())
    throw std::invalid_argument("product image: the alpha is not the frame's size");
  if (!(options.marginFraction >= 0.0 && options.marginFraction < 0.45))
    throw std::invalid_argument("product image: the margin must be in [0, 0.45)");
  const cv::Rect box = cv::boundingRect(alpha > 0.0f);
  if (box.area() == 0)
    throw std::invalid_argument("product image: the garment mask is empty");
  const double fill = 1.0 - 2.0 * options.marginFraction;
  ProductImages out;
  out.garmentBox = box;
  const int side = static_cast<int>(std::ceil(std::max(box.width, box.height) / fill));
  out.square = sized(onWhite(bgr, alpha, box, {side, side}, options.shadow), options.minSidePx,
                     options.maxSidePx);
  // 4:5 (width:height), the garment fitting both ways with the margin.
  const int h = static_cast<int>(
      std::ceil(std::max(static_cast<double>(box.height), 1.25 * box.width) / fill));
  const int w = std::max(box.width, static_cast<int>(std::lround(0.8 * h)));
  out.portrait = sized(onWhite(bgr, alpha, box, {w, std::max(h, box.height)}, options.shadow),
                       options.minSidePx, options.maxSidePx);
  // The transparent cut-out: the box with the margin, straight (not premultiplied) alpha.
  const int m =
      static_cast<int>(std::lround(options.marginFraction * std::max(box.width, box.height)));
  const cv::Rect padded(box.x - m, box.y - m, box.width + 2 * m, box.height + 2 * m);
  cv::Mat4b cut(padded.size(), cv::Vec4b(0, 0, 0, 0));
  const cv::Rect inFrame = padded & cv::Rect(0, 0, bgr.cols, bgr.rows);
  for (int y = inFrame.y; y < inFrame.y + inFrame.height; ++y) {
    const cv::Vec3b* src = bgr.ptr<cv::Vec3b>(y);
    const float* a = alpha.ptr<float>(y);
    cv::Vec4b* dst = cut.ptr<cv::Vec4b>(y - padded.y);
    for (int x = inFrame.x; x < inFrame.x + inFrame.width; ++x) {
      const uchar al = cv::saturate_cast<uchar>(a[x] * 255.f);
      if (al > 0)
        dst[x - padded.x] = cv::Vec4b(src[x][0], src[x][1], src[x][2], al);
    }
  }
  const int cutSide = std::max(cut.cols, cut.rows);
  if (options.maxSidePx > 0 && cutSide > options.maxSidePx) {
    const double f = static_cast<double>(options.maxSidePx) / cutSide;
    cv::resize(cut, cut, cv::Size(), f, f, cv::INTER_AREA);
  }
  out.cutout = cut;
  out.cutoutRect = padded;
  return out;
}

ProductLayer productLayer(const cv::Mat3b& dressed, const cv::Mat1b& mask, const cv::Mat3b& bare,
                          const cv::Vec3b& screenBgr, const ProductImageOptions& options) {
  if (!(options.pxPerCm > 0))
    throw std::invalid_argument("product image: px per cm must be positive");
  if (mask.size() != dressed.size() || (!bare.empty() && bare.size() != dressed.size()))
    throw std::invalid_argument(
        "product image: the frame, the bare frame and the mask differ in size");
  const double s = options.pxPerCm;
  const int guideR = std::max(2, static_cast<int>(std::lround(kGuideRadiusCm * s)));
  cv::Mat1f alpha = refinedAlpha(dressed, mask, guideR);
  if (!bare.empty()) {
    // The cut covers the outside too: the guided filter's ramp reaches a few px beyond the mask,
    // and what of it still looks as the bare frame did is no garment either.
    // The alpha is 0 beyond guideR of the mask (refinedAlpha's band), so the cut matters only
    // that near; formRemainsNear keeps it exact 2 px less far than it tests.
    const cv::Mat1b cut =
        formRemainsNear(dressed, bare, mask, std::max(3.0, kFormBandCm * s), kFormDeltaE, screenBgr,
                        options.wholeCropPasses ? -1 : guideR + 3);
    alpha.setTo(0.0f, cut);
  }
  cv::Mat3b colour = dressed.clone();
  if (!bare.empty())
    unmixEdge(colour, alpha, bare);
  despillEdgeImpl(colour, alpha, screenBgr, std::max(3.0, kSpillBandCm * s),
                  !options.wholeCropPasses);
  return {colour, alpha};
}

ProductImages productPhotos(const cv::Mat3b& dressed, const cv::Mat1b& mask, const cv::Mat3b& bare,
                            const cv::Vec3b& screenBgr, const ProductImageOptions& options) {
  const ProductLayer layer = productLayer(dressed, mask, bare, screenBgr, options);
  return makeProductImages(layer.colour, layer.alpha, options);
}

}  // namespace garmcap::pipeline
