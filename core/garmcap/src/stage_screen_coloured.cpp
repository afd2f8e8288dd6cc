#include "stage_screen_coloured.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "frame_ops.h"

namespace garmcap::pipeline {
namespace {

// A garment is taken for screen-coloured when more than this much of it, over the form, keys as
// screen (sensor noise leaves well under 1 cm2).
constexpr double kScreenColouredCm2 = 1.0;
// Notches up to twice this tall in a screen-coloured garment's sides are filled where the frame
// changed (a check or stripe the colour of the screen at the edge).
constexpr double kPatternNotchCm = 1.25;

// Where both keys see the screen, how the dressed frame differs from the bare one beyond sensor
// noise, from per-channel log ratios after a 0.15 cm blur: `changed` by the largest of them,
// `recoloured` by their spread. A shadow dims all three channels alike, so only a garment
// recolours the screen. Most of the screen is unchanged, so the noise floors are read over all
// of `where`.
ScreenChange changedScreen(const cv::Mat& bareW, const cv::Mat& dressedW, const cv::Mat& where,
                           double pxPerCm) {
  const double sigma = std::max(0.7, 0.15 * pxPerCm);
  cv::Mat e, d;
  bareW.convertTo(e, CV_32FC3, 1.0, 1.0);
  dressedW.convertTo(d, CV_32FC3, 1.0, 1.0);
  cv::GaussianBlur(e, e, cv::Size(), sigma);
  cv::GaussianBlur(d, d, cv::Size(), sigma);
  cv::Mat1f change(e.size()), spread(e.size());
  cv::parallel_for_(cv::Range(0, e.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3f* pe = e.ptr<cv::Vec3f>(y);
      const cv::Vec3f* pd = d.ptr<cv::Vec3f>(y);
      float* c = change.ptr<float>(y);
      float* sp = spread.ptr<float>(y);
      for (int x = 0; x < e.cols; ++x) {
        float lo = 0, hi = 0, m = 0;
        for (int k = 0; k < 3; ++k) {
          const float r = std::log(pd[x][k] / pe[x][k]);
          lo = k == 0 ? r : std::min(lo, r);
          hi = k == 0 ? r : std::max(hi, r);
          m = std::max(m, std::abs(r));
        }
        c[x] = m;
        sp[x] = hi - lo;
      }
    }
  });
  std::vector<float> changeSample, spreadSample;
  for (int y = 0; y < e.rows; ++y) {
    const uchar* w = where.ptr(y);
    for (int x = (7 - y % 7) % 7; x < e.cols; x += 7)
      if (w[x]) {
        changeSample.push_back(change(y, x));
        spreadSample.push_back(spread(y, x));
      }
  }
  ScreenChange out;
  if (changeSample.size() < 1000) {
    out.changed = out.recoloured = cv::Mat::zeros(e.size(), CV_8UC1);
    return out;
  }
  const float tauChange = static_cast<float>(noiseThreshold(changeSample, kNoiseSigmas));
  const float tauSpread = static_cast<float>(noiseThreshold(spreadSample, kNoiseSigmas));
  out.changed = (change > tauChange) & where;
  out.recoloured = (spread > tauSpread) & out.changed;
  return out;
}

}  // namespace

std::optional<ScreenChange> screenColouredChange(const calib::KeyResult& keyE,
                                                 const calib::KeyResult& keyD,
                                                 const cv::Mat& formInside,
                                                 const cv::Mat& formOutline, const cv::Mat& fgD,
                                                 double pxPerCm,
                                                 std::vector<std::string>& warnings) {
  // Counted after an opening: where the two keys place the form's outline a few pixels apart
  // (the garment's shadow shifts the dressed key's screen estimate), a thin line is left.
  cv::Mat insideKeyedScreen = formInside & ~keyD.mask;
  cv::morphologyEx(insideKeyedScreen, insideKeyedScreen, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  const double keyedAsScreenCm2 = cv::countNonZero(insideKeyedScreen) / (pxPerCm * pxPerCm);
  if (keyedAsScreenCm2 <= kScreenColouredCm2)
    return std::nullopt;
  ScreenChange change = changedScreen(keyE.despilled, keyD.despilled, ~fgD, pxPerCm);
  // The form's mixed outline pixels change colour with any sub-pixel shift: no evidence.
  change.recoloured &= ~formOutline;
  warnings.push_back("the garment is close to the screen's colour (" +
                     std::to_string(std::lround(keyedAsScreenCm2)) +
                     " cm2 of it over the form keys as screen); its outline was found "
                     "against the bare-form frame, check it");
  return change;
}

cv::Mat repairScreenColouredGarment(const cv::Mat& garmentW, const cv::Mat& fgD,
                                    const cv::Mat& exposed, const ScreenChange& change,
                                    double pxPerCm) {
  // What GrabCut took from the changed screen must be a region, not the thin halo of blur
  // and mixed pixels around an outline the key already placed.
  const cv::Mat kernelHalo = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3));
  cv::Mat beyondKey = garmentW & ~fgD;
  cv::morphologyEx(beyondKey, beyondKey, cv::MORPH_OPEN, kernelHalo);
  cv::Mat garment = (garmentW & fgD) | beyondKey;
  // A pattern's screen-coloured squares or stripes at the outline look like the garment's own
  // shadow, and GrabCut cuts around them: notches a pattern repeat deep in the garment's sides.
  // They are closed along the vertical only (a horizontal closing would bridge the gap between
  // the legs below the crotch) and over what changed since the bare frame only (changed
  // screen, form that is not exposed).
  const int rc = std::max(2, static_cast<int>(std::lround(kPatternNotchCm * pxPerCm)));
  cv::Mat closed;
  cv::morphologyEx(garment, closed, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, 2 * rc + 1)));
  garment |= closed & (change.changed | (fgD & ~exposed));
  return garment;
}

}  // namespace garmcap::pipeline
