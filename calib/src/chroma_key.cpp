#include "garmcap/calib/chroma_key.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "garmcap/calib/errors.h"

namespace garmcap::calib {

namespace {

// Normalised convolution: the weighted average of a value over a Gaussian neighbourhood, using
// only pixels with weight > 0, from `valueTimesWeight` and `weight`; computed on a reduced image
// because the screen varies slowly.
cv::Mat1f smoothFill(const cv::Mat1f& valueTimesWeight, const cv::Mat1f& weight,
                     double sigmaFraction, double minWeight) {
  const int maxDim = std::max(weight.cols, weight.rows);
  const double f = std::min(1.0, 256.0 / maxDim);
  cv::Mat1f v, w;
  cv::resize(valueTimesWeight, v, cv::Size(), f, f, cv::INTER_AREA);
  cv::resize(weight, w, cv::Size(), f, f, cv::INTER_AREA);
  const double sigma = std::max(1.0, sigmaFraction * std::max(v.cols, v.rows));
  cv::GaussianBlur(v, v, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
  cv::GaussianBlur(w, w, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
  cv::Mat1f out = v / cv::max(w, minWeight);
  cv::Mat1f full;
  cv::resize(out, full, weight.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

// Spill tints a light surface towards the screen's colour but does not make it brighter than the
// screen's own light there, so a pixel this much brighter than the screen would be is foreground
// whatever its greenness: under strong spill the edges of light fabric keyed as screen, 0.3-0.8 cm
// a side. The screen's brightness follows its greenness (one colour under varying light), so it
// is read off the screen-greenness field. Assumes a matte screen (no glare hot spots).
constexpr float kBrighterThanScreen = 1.3f;
// Before the form's own luminance near its edge is known, only a pixel this much brighter than the
// screen is taken for foreground on brightness alone (a half-mixed edge pixel of a white subject
// reaches ~1.7 x, of a beige one ~1.5 x).
constexpr float kSurelyBrighter = 1.6f;

float luminance(const cv::Vec3b& p) {
  return (static_cast<float>(p[0]) + static_cast<float>(p[1]) + static_cast<float>(p[2])) / 3.0f;
}

// Coverage by luminance unmixing, for a subject clearly brighter than the screen (else 0): spill
// moves a light edge pixel's greenness towards the screen's but keeps its luminance, so the
// larger of this and the greenness unmixing is the pixel's coverage. Mixed pixels give both the
// same value.
float luminanceAlpha(float lum, float lumScreen, float lumForm) {
  if (!(lumForm > kBrighterThanScreen * lumScreen))
    return 0.0f;
  return std::clamp((lum - lumScreen) / (lumForm - lumScreen), 0.0f, 1.0f);
}

// The key's form luminance at pixel (x, y) of the keyed frame; 0 where it was not estimated.
float formLuminanceAt(const KeyResult& k, int x, int y) {
  if (k.formLuminance.empty() || x < k.formLuminanceRoi.x || y < k.formLuminanceRoi.y)
    return 0.0f;
  const int sx = (x - k.formLuminanceRoi.x) / 2, sy = (y - k.formLuminanceRoi.y) / 2;
  if (sx >= k.formLuminance.cols || sy >= k.formLuminance.rows)
    return 0.0f;
  return k.formLuminance(sy, sx);
}

// Luminance of the screen per unit of its greenness, from its border colour.
float screenLuminancePerGreenness(const cv::Vec3b& screenBgr) {
  const float g =
      static_cast<float>(screenBgr[1]) - static_cast<float>(std::max(screenBgr[0], screenBgr[2]));
  return luminance(screenBgr) / std::max(1.0f, g);
}

}  // namespace

KeyResult keyGreenScreen(const cv::Mat3b& frame, const std::string& what, const KeyOptions& opt) {
  if (frame.empty())
    throw CalibError(CalibErrorKind::kNoFormInFrame, what + ": empty image");
  KeyResult r;
  // 1. The screen colour from the border ring.
  const int ring =
      std::max(3, static_cast<int>(opt.borderFraction * std::min(frame.cols, frame.rows)));
  std::vector<cv::Vec3b> border;
  for (int y = 0; y < frame.rows; ++y) {
    const bool edgeRow = y < ring || y >= frame.rows - ring;
    for (int x = 0; x < frame.cols; x += (edgeRow ? 1 : 1)) {
      if (!edgeRow && x == ring)
        x = frame.cols - ring;
      border.push_back(frame(y, x));
    }
  }
  auto median = [&](int c) {
    std::vector<int> v;
    v.reserve(border.size());
    for (const auto& p : border)
      v.push_back(p[c]);
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  r.screenBgr = cv::Vec3b(static_cast<uchar>(median(0)), static_cast<uchar>(median(1)),
                          static_cast<uchar>(median(2)));
  cv::Mat3b one(1, 1, r.screenBgr), hsv;
  cv::cvtColor(one, hsv, cv::COLOR_BGR2HSV_FULL);
  r.screenHueDeg = hsv(0, 0)[0] * 360.0 / 256.0;
  const double sat = hsv(0, 0)[1] / 255.0;
  std::size_t greenBorder = 0;
  for (const auto& p : border) {
    if (p[1] > std::max(p[0], p[2]) + 20)
      ++greenBorder;
  }
  const double greenShare = static_cast<double>(greenBorder) / static_cast<double>(border.size());
  if (r.screenHueDeg < 75 || r.screenHueDeg > 165 || sat < 0.25 || greenShare < 0.6) {
    std::ostringstream msg;
    msg << what << ": the background is not a green screen (border median BGR("
        << int(r.screenBgr[0]) << "," << int(r.screenBgr[1]) << "," << int(r.screenBgr[2])
        << "), hue " << std::round(r.screenHueDeg) << " deg, saturation " << std::round(sat * 100)
        << "%, green share of the border " << std::round(greenShare * 100)
        << "%); light the screen evenly and fill the frame border with it";
    throw CalibError(CalibErrorKind::kNotGreenScreen, msg.str());
  }

  // 2. Greenness and the screen's greenness per pixel. One pass per step over the frame: at
  // 2 MP the whole-image float expressions (convert, split, max, compare) cost ~100 ms.
  const float gBorder = static_cast<float>(r.screenBgr[1]) -
                        static_cast<float>(std::max(r.screenBgr[0], r.screenBgr[2]));
  cv::Mat1f g(frame.size()), screenW(frame.size()), gOnScreen(frame.size());
  cv::parallel_for_(cv::Range(0, frame.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* p = frame.ptr<cv::Vec3b>(y);
      float* gr = g.ptr<float>(y);
      float* wr = screenW.ptr<float>(y);
      float* vr = gOnScreen.ptr<float>(y);
      for (int x = 0; x < frame.cols; ++x) {
        const float gv =
            static_cast<float>(p[x][1]) - static_cast<float>(std::max(p[x][0], p[x][2]));
        const bool screen = gv > 0.5f * gBorder;
        gr[x] = gv;
        wr[x] = screen ? 1.0f : 0.0f;
        vr[x] = screen ? gv : 0.0f;
      }
    }
  });
  cv::Mat1f gScreen = smoothFill(gOnScreen, screenW, 0.08, 1e-3);

  // 3. Binary mask: nearer to the form than to the screen; largest component only.
  cv::Mat1b mask(frame.size());
  const float lumPerGreen = screenLuminancePerGreenness(r.screenBgr);
  const float brightLimit = kSurelyBrighter * lumPerGreen;
  cv::parallel_for_(cv::Range(0, frame.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* gs = gScreen.ptr<float>(y);
      const float* gr = g.ptr<float>(y);
      const cv::Vec3b* p = frame.ptr<cv::Vec3b>(y);
      uchar* m = mask.ptr<uchar>(y);
      for (int x = 0; x < frame.cols; ++x) {
        gs[x] = std::max(gs[x], 0.25f * gBorder);
        m[x] = gr[x] / gs[x] < 0.5f || luminance(p[x]) > brightLimit * gs[x] ? 255 : 0;
      }
    }
  });
  r.screenGreenness = gScreen;
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, {3, 3}));
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  int best = 0, bestArea = 0;
  for (int i = 1; i < n; ++i) {
    const int a = stats.at<int>(i, cv::CC_STAT_AREA);
    if (a > bestArea)
      best = i, bestArea = a;
  }
  const double minArea = opt.minForegroundFraction * frame.total();
  if (best == 0 || bestArea < minArea) {
    std::ostringstream msg;
    msg << what << ": no form in the frame (largest foreground region " << bestArea
        << " px, at least " << static_cast<long>(minArea) << " px expected)";
    throw CalibError(CalibErrorKind::kNoFormInFrame, msg.str());
  }
  mask = labels == best;
  // Fill small holes (noise, specular spots) but keep real openings such as the gap between an
  // arm and the torso.
  {
    cv::Mat1b inv = ~mask;
    cv::Mat1i hl;
    cv::Mat hs, hc;
    const int hn = cv::connectedComponentsWithStats(inv, hl, hs, hc, 4, CV_32S);
    // One pass over the image with a per-label decision: noise leaves thousands of tiny holes
    // at 12 MP, and a full-image compare per hole cost seconds.
    std::vector<uchar> fill(static_cast<std::size_t>(hn), 0);
    bool any = false;
    for (int i = 1; i < hn; ++i) {
      const int x = hs.at<int>(i, cv::CC_STAT_LEFT), y = hs.at<int>(i, cv::CC_STAT_TOP);
      const int w = hs.at<int>(i, cv::CC_STAT_WIDTH), h = hs.at<int>(i, cv::CC_STAT_HEIGHT);
      const bool touchesBorder = x == 0 || y == 0 || x + w == frame.cols || y + h == frame.rows;
      if (!touchesBorder && hs.at<int>(i, cv::CC_STAT_AREA) < 0.001 * bestArea) {
        fill[static_cast<std::size_t>(i)] = 1;
        any = true;
      }
    }
    if (any) {
      for (int y = 0; y < mask.rows; ++y) {
        const int* lab = hl.ptr<int>(y);
        uchar* m = mask.ptr<uchar>(y);
        for (int x = 0; x < mask.cols; ++x)
          if (fill[static_cast<std::size_t>(lab[x])])
            m[x] = 255;
      }
    }
  }
  const int l = stats.at<int>(best, cv::CC_STAT_LEFT), t = stats.at<int>(best, cv::CC_STAT_TOP);
  const int w = stats.at<int>(best, cv::CC_STAT_WIDTH), h = stats.at<int>(best, cv::CC_STAT_HEIGHT);
  r.cutAtBottom = t + h == frame.rows;
  if (l == 0 || t == 0 || l + w == frame.cols || (r.cutAtBottom && !opt.allowCutAtBottom)) {
    std::ostringstream msg;
    msg << what << ": the form is cut off by the frame edge (its silhouette touches the "
        << (t == 0                ? "top"
            : l == 0              ? "left"
            : l + w == frame.cols ? "right"
                                  : "bottom")
        << " edge); move the camera back or zoom out so that "
        << (opt.allowCutAtBottom ? "the form is in view from its top (head or neck cap) and "
                                   "its sides down past its hips (its legs or stand may leave "
                                   "the frame at the bottom)"
                                 : "the whole form is in view");
    throw CalibError(CalibErrorKind::kFormCutOff, msg.str());
  }

  // 4. Soft alpha in a band around the edge: unmix with the local form greenness.
  const int band = std::max(1, opt.edgeBandPx);
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * band + 1, 2 * band + 1});
  cv::Mat1b inner, outer;
  cv::erode(mask, inner, kernel);
  cv::dilate(mask, outer, kernel);
  // The form's own greenness near its edge: a normalised convolution of the inner form's
  // greenness, a fine blur because the form's colour varies. Only the edge band reads it, so it
  // runs on the band's box plus the kernel's reach, and at half resolution (the form's greenness
  // varies slowly; at 2 MP the full-resolution blur over the whole frame cost ~100 ms).
  const double s = 3.0 * band;
  const int reach = cvCeil(4.0 * s) + 2;
  const cv::Rect bandBox = cv::boundingRect(outer);
  const cv::Rect roi = cv::Rect(bandBox.x - reach, bandBox.y - reach, bandBox.width + 2 * reach,
                                bandBox.height + 2 * reach) &
                       cv::Rect(0, 0, frame.cols, frame.rows);
  cv::Mat1f gForm;
  {
    cv::Mat1f ww = cv::Mat1f::zeros(roi.size());
    ww.setTo(1.0f, inner(roi));
    cv::Mat1f gw = g(roi).mul(ww), gwSmall, wwSmall;
    cv::resize(gw, gwSmall, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    cv::resize(ww, wwSmall, gwSmall.size(), 0, 0, cv::INTER_AREA);
    cv::GaussianBlur(gwSmall, gwSmall, cv::Size(), s / 2, s / 2);
    const cv::Mat1f wwUnblurred = wwSmall.clone();
    cv::GaussianBlur(wwSmall, wwSmall, cv::Size(), s / 2, s / 2);
    cv::resize(gwSmall / cv::max(wwSmall, 1e-4f), gForm, roi.size(), 0, 0, cv::INTER_LINEAR);
    // The same for the form's luminance, which spill leaves (it tints, it does not brighten);
    // kept at half resolution over the ROI, where edge pixels read it.
    cv::Mat3b half;
    cv::resize(frame(roi), half, wwSmall.size(), 0, 0, cv::INTER_AREA);
    cv::Mat1f lwSmall(half.size());
    for (int y = 0; y < half.rows; ++y) {
      const cv::Vec3b* p = half.ptr<cv::Vec3b>(y);
      const float* wr = wwUnblurred.ptr<float>(y);
      float* lr = lwSmall.ptr<float>(y);
      for (int x = 0; x < half.cols; ++x)
        lr[x] = wr[x] * luminance(p[x]);
    }
    cv::GaussianBlur(lwSmall, lwSmall, cv::Size(), s / 2, s / 2);
    r.formLuminance = lwSmall / cv::max(wwSmall, 1e-4f);
    r.formLuminanceRoi = roi;
  }
  r.alpha = cv::Mat1f::zeros(g.size());
  cv::parallel_for_(cv::Range(0, g.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const uchar* in = inner.ptr(y);
      const uchar* out = outer.ptr(y);
      const float* gr = g.ptr<float>(y);
      const float* gsr = gScreen.ptr<float>(y);
      const cv::Vec3b* p = frame.ptr<cv::Vec3b>(y);
      float* a = r.alpha.ptr<float>(y);
      for (int x = 0; x < g.cols; ++x) {
        if (in[x]) {
          a[x] = 1.0f;
        } else if (out[x]) {
          // Outer band pixels lie inside the ROI by construction.
          const float gs = gsr[x];
          const float gf = std::min(gForm(y - roi.y, x - roi.x), 0.5f * gs);
          a[x] = std::clamp((gs - gr[x]) / (gs - gf), 0.0f, 1.0f);
          a[x] = std::max(
              a[x], luminanceAlpha(luminance(p[x]), gs * lumPerGreen, formLuminanceAt(r, x, y)));
        }
      }
    }
  });
  r.mask = r.alpha > 0.5f;

  // 5. Spill suppression on the foreground.
  r.despilled = frame.clone();
  despill(r.despilled, outer);
  return r;
}

void despill(cv::Mat3b& bgr, const cv::Mat1b& mask) {
  if (mask.size() != bgr.size())
    throw std::invalid_argument("despill: the mask is not the image's size");
  cv::parallel_for_(cv::Range(0, bgr.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const uchar* m = mask.ptr(y);
      cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
      for (int x = 0; x < bgr.cols; ++x)
        if (m[x])
          row[x][1] = std::min(row[x][1], std::max(row[x][0], row[x][2]));
    }
  });
}

cv::Mat1b foregroundInRegion(const cv::Mat3b& fullBgr, const KeyResult& workKey,
                             const cv::Mat1b& where) {
  if (where.size() != fullBgr.size())
    throw std::invalid_argument("foregroundInRegion: the region is not the frame's size");
  const cv::Mat1f& gs = workKey.screenGreenness;
  if (gs.empty())
    throw std::invalid_argument("foregroundInRegion: the key holds no screen greenness");
  const float lumPerGreen = screenLuminancePerGreenness(workKey.screenBgr);
  const double fx = static_cast<double>(gs.cols) / fullBgr.cols;
  const double fy = static_cast<double>(gs.rows) / fullBgr.rows;
  cv::Mat1b out = cv::Mat1b::zeros(fullBgr.size());
  cv::parallel_for_(cv::Range(0, fullBgr.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const uchar* w = where.ptr(y);
      const cv::Vec3b* p = fullBgr.ptr<cv::Vec3b>(y);
      const float* screen = gs.ptr<float>(std::min(gs.rows - 1, static_cast<int>(y * fy)));
      uchar* o = out.ptr(y);
      for (int x = 0; x < fullBgr.cols; ++x) {
        if (!w[x])
          continue;
        const float g = static_cast<float>(p[x][1]) - std::max(p[x][0], p[x][2]);
        const float s = screen[std::min(gs.cols - 1, static_cast<int>(x * fx))];
        const float lf =
            formLuminanceAt(workKey, static_cast<int>(x * fx), static_cast<int>(y * fy));
        o[x] =
            g < 0.5f * s || luminanceAlpha(luminance(p[x]), s * lumPerGreen, lf) > 0.5f ? 255 : 0;
      }
    }
  });
  return out;
}

}  // namespace garmcap::calib
