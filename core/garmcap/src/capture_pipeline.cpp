#include "garmcap/pipeline/capture_pipeline.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string_view>

#include "garmcap/calib/chroma_key.h"
#include "garmcap/calib/errors.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/draft_from_garment.h"
#include "garmcap/pipeline/frame_motion.h"
#include "garmcap/pipeline/grabcut_refine.h"
#include "garmcap/pipeline/product_images.h"
#include "garmcap/pipeline/texture.h"

namespace garmcap::pipeline {
namespace {

using Clock = std::chrono::steady_clock;
using Reason = CaptureError::Reason;

// Camera or form shifts below this are re-registered; above it the capture is refused.
constexpr double kMaxShiftCm = 1.0;
constexpr double kMinShiftPx = 1.0;
// The work frames' denoising blur, in work-frame px.
constexpr double kDenoiseSigmaPx = 0.7;
// Shops zoom product photos of 2048 px and more: from a frame that large, the photos reach it
// (scaled up by 1.5x at most when the garment spans less of the frame).
constexpr int kShopZoomPx = 2048;
// Below the hip, pants part into legs for at least this long (the shortest shorts' inseam).
constexpr double kPartedLegsCm = 5.0;
// A dress's skirt covers the centre line at least this far below the crotch (the shortest
// dress the type database draws ends 4 cm below it on the bundled form).
constexpr double kSkirtBelowCrotchCm = 3.0;
// Dressed foreground this far from the exposed form is garment without asking GrabCut.
constexpr double kSettledCm = 2.0;
// Exposed form whose difference is below this fraction of the noise thresholds is sure form from
// this far from any garment evidence (a garment the colour of the form reads near the threshold,
// and keeps the wider margin above for GrabCut to find it).
constexpr double kClearlyExposed = 0.5;
constexpr double kClearlySettledCm = 0.5;
// Notches up to twice this tall in a screen-coloured garment's sides are filled where the frame
// changed (a check or stripe the colour of the screen at the edge).
constexpr double kPatternNotchCm = 1.25;
// A "sleeve" no longer than a sleeveless reference top reaches down this form's arm plus this is
// the bodice's shoulder.
constexpr double kSleevelessMarginCm = 0.75;
// The colour-difference noise floor is read on the form from this far above its side neck up.
constexpr double kNoiseAboveNeckCm = 4.0;
constexpr double kNoiseSigmas = 6.0;
constexpr double kAveragedDifferenceCm = 0.5;
// A garment is taken for screen-coloured when more than this much of it, over the form, keys as
// screen (sensor noise leaves well under 1 cm2).
constexpr double kScreenColouredCm2 = 1.0;

// The garment's shadow on the form (shadowOnForm): at least this much darker in Lab lightness
// (0-255), with a chroma change of at most this fraction of the darkening plus a constant.
constexpr float kShadowMinDarkening = 8.0f;
constexpr float kShadowChromaPerLightness = 0.2f;
constexpr float kShadowChroma = 4.0f;
constexpr double kShadowBlurCm = 0.2;
// A shadow band is at least this wide (thinner is a garment's stripe or print, shaded).
constexpr double kShadowMinWidthCm = 0.8;
// More of the changed form than this looking like shadow is a dark neutral garment.
constexpr double kShadowMaxShareOfChange = 0.4;

class StageTimer {
 public:
  StageTimer(std::vector<StageTiming>& out, const std::function<void(const StageTiming&)>& onDone)
      : out_(out), onDone_(onDone), start_(Clock::now()) {}
  void done(const std::string& stage) {
    const auto now = Clock::now();
    out_.push_back({stage, std::chrono::duration<double, std::milli>(now - start_).count()});
    start_ = now;
    if (onDone_)
      onDone_(out_.back());
  }

 private:
  std::vector<StageTiming>& out_;
  const std::function<void(const StageTiming&)>& onDone_;
  Clock::time_point start_;
};

std::string fmt1(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

cv::Mat rotateAbout(const cv::Mat& img, const Eigen::Vector2d& centre, double rollRad, int interp) {
  // The pose rotates the world counter-clockwise on screen by roll; undo it.
  const cv::Mat m = cv::getRotationMatrix2D(
      cv::Point2f(static_cast<float>(centre.x()), static_cast<float>(centre.y())),
      -rollRad * 180.0 / M_PI, 1.0);
  cv::Mat out;
  cv::warpAffine(img, out, m, img.size(), interp, cv::BORDER_REPLICATE);
  return out;
}

calib::KeyResult key(const cv::Mat& bgr, const std::string& what) {
  try {
    return calib::keyGreenScreen(bgr, what);
  } catch (const calib::CalibError& e) {
    switch (e.kind()) {
      case calib::CalibErrorKind::kFormCutOff:
        throw CaptureError(
            Reason::kOffForm,
            std::string("the garment or form reaches the edge of the ") + what + ": " + e.what());
      case calib::CalibErrorKind::kNoFormInFrame:
        throw CaptureError(Reason::kBadInput,
                           std::string("nothing stands in front of the green screen in the ") +
                               what + ": " + e.what());
      default:
        throw CaptureError(Reason::kBadInput, e.what());
    }
  }
}

// The largest 8-connected piece of a mask; empty when the mask is.
cv::Mat largestComponent(const cv::Mat& mask) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  int best = 0, bestArea = 0;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) > bestArea) {
      bestArea = stats.at<int>(i, cv::CC_STAT_AREA);
      best = i;
    }
  return bestArea == 0 ? cv::Mat() : cv::Mat(labels == best);
}

// Both work frames get the same light blur before segmentation: GrabCut's colour models and
// contrast term are fitted to pixel values, and sensor noise on a dark or finely shaded garment
// spreads its model over the form's colours. Edges move by no more than the blur.
cv::Mat denoised(const cv::Mat& bgr) {
  cv::Mat out;
  cv::GaussianBlur(bgr, out, cv::Size(3, 3), kDenoiseSigmaPx);
  return out;
}

// The bare-form frame as segmentation uses it: its de-rolled work frame's side of the motion
// estimate, and its key.
struct BareFrame {
  std::optional<MotionReference> motion;
  calib::KeyResult key;
  // The undistorted bare frame at full resolution, de-rolled as the dressed one is: the product
  // photos cut what still looks as it did here.
  cv::Mat uprightFull;
};

// The bare-form frame is the same for every garment captured after one bare-form capture, so it
// is prepared once and found again by a hash of its pixels, the camera model and the work
// geometry (a few ms at 12 MP against ~100 ms of undistorting, downscaling, de-rolling, edges and
// keying). Shared read-only. `camera` is the calibration's camera model, or null.
std::shared_ptr<const BareFrame> prepareBareFrame(const cv::Mat& emptyRaw,
                                                  const calib::CameraModel* camera,
                                                  const calib::FrameUndistorter* undistorter,
                                                  double ws, const Eigen::Vector2d& centreW,
                                                  double rollRad, int topBandEndRow,
                                                  int bottomBandStartRow) {
  static std::mutex mutex;
  static std::size_t cachedHash = 0;
  static std::shared_ptr<const BareFrame> cached;
  const cv::Mat c = emptyRaw.isContinuous() ? emptyRaw : emptyRaw.clone();
  std::size_t h = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(c.data), c.total() * c.elemSize()));
  std::vector<double> keyed = {ws,
                               centreW.x(),
                               centreW.y(),
                               rollRad,
                               static_cast<double>(c.cols),
                               static_cast<double>(c.rows),
                               static_cast<double>(topBandEndRow),
                               static_cast<double>(bottomBandStartRow),
                               camera ? 1.0 : 0.0};
  if (camera) {
    for (int i = 0; i < 9; ++i)
      keyed.push_back(camera->cameraMatrix.val[i]);
    keyed.insert(keyed.end(), camera->distortion.begin(), camera->distortion.end());
  }
  for (const double v : keyed)
    h ^= std::hash<double>{}(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (cached && cachedHash == h)
      return cached;
  }
  const cv::Mat emptyFull = undistorter ? undistorter->apply(emptyRaw) : emptyRaw;
  cv::Mat work = emptyFull;
  if (ws < 1.0)
    cv::resize(emptyFull, work, cv::Size(), ws, ws, cv::INTER_AREA);
  if (std::abs(rollRad) > 1e-6)
    work = rotateAbout(work, centreW, rollRad, cv::INTER_LINEAR);
  work = denoised(work);
  auto bare = std::make_shared<BareFrame>();
  // Its own pixels, never the caller's frame: the cache outlives the call.
  if (std::abs(rollRad) > 1e-6)
    bare->uprightFull = rotateAbout(emptyFull, centreW / ws, rollRad, cv::INTER_LINEAR);
  else
    bare->uprightFull = emptyFull.data == emptyRaw.data ? emptyRaw.clone() : emptyFull;
  bare->motion.emplace(work, topBandEndRow, bottomBandStartRow);
  bare->key = key(work, "bare-form frame");
  std::lock_guard<std::mutex> lock(mutex);
  cachedHash = h;
  cached = bare;
  return bare;
}

// The garment mask at full resolution from the work-frame one. Where the garment meets the screen
// the full frame's own key places the edge (to the pixel); where it meets the form, or inside,
// the work-frame decision is upsampled. Only a band of a few work pixels around the outline is
// keyed again, so this costs a few percent of a full-frame key.
cv::Mat garmentAtFullResolution(const cv::Mat& dressedFull, const calib::KeyResult& keyW,
                                const cv::Mat& garmentW, const cv::Mat& formW) {
  // Let the garment reach two work pixels further where the bare frame shows the screen: the
  // full frame's key then decides where it ends there (the work cut may stop a pixel short of
  // the screen at mixed edge pixels). Over the form it stays as the work frame cut it.
  cv::Mat grown;
  cv::dilate(garmentW, grown, cv::Mat(), cv::Point(-1, -1), 2);
  const cv::Mat extended = garmentW | (grown & ~formW);
  cv::Mat bandW;
  cv::morphologyEx(garmentW, bandW, cv::MORPH_GRADIENT, cv::Mat());
  cv::dilate(bandW, bandW, cv::Mat(), cv::Point(-1, -1), 2);
  cv::Mat up, band;
  cv::resize(extended, up, dressedFull.size(), 0, 0, cv::INTER_LINEAR);
  cv::resize(bandW, band, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat full;
  cv::resize(garmentW, full, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
  const cv::Mat1b fg = calib::foregroundInRegion(dressedFull, keyW, band);
  // The full frame's key decides only where the work frame's key saw a foreground too: a garment
  // close to the screen's colour was found against the bare frame, and the key would cut it
  // back. There the work decision is upsampled smoothly instead.
  cv::Mat keyed;
  cv::dilate(keyW.mask | formW, keyed, cv::Mat(), cv::Point(-1, -1), 3);
  cv::Mat inBand = (up >= 128) & fg;
  if (cv::countNonZero(bandW & ~keyed) > 0) {
    cv::Mat keyedUp, smooth;
    cv::resize(keyed, keyedUp, dressedFull.size(), 0, 0, cv::INTER_NEAREST);
    cv::resize(garmentW, smooth, dressedFull.size(), 0, 0, cv::INTER_LINEAR);
    inBand = (inBand & keyedUp) | ((smooth >= 128) & ~keyedUp);
  }
  inBand.copyTo(full, band);
  return full;
}

// The Lab difference of the two frames averaged over about sigmaPx before taking its size
// (a,b magnitude plus half of L, as the fine difference): sensor noise averages out, while a
// garment the colour of the form keeps its small, steady offset and its folds. Each channel is
// clipped at `clip` first, so that a strong garment edge spreads only a thin halo. Only pixels of
// `over` (the form) are averaged: the garment's shadow changes the screen beside the form, and
// that change must not reach the form's own edge pixels.
cv::Mat1f averagedDifference(const cv::Mat& labE, const cv::Mat& labD, const cv::Mat& over,
                             double sigmaPx, float clip) {
  // One pass for the weighted, clipped signed difference (at 2 MP the chain of whole-image
  // operations cost ~100 ms more).
  cv::Mat3f weighted(labE.size());
  cv::Mat1f weight(labE.size());
  cv::parallel_for_(cv::Range(0, labE.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* e = labE.ptr<cv::Vec3b>(y);
      const cv::Vec3b* d = labD.ptr<cv::Vec3b>(y);
      const uchar* o = over.ptr(y);
      cv::Vec3f* wd = weighted.ptr<cv::Vec3f>(y);
      float* w = weight.ptr<float>(y);
      for (int x = 0; x < labE.cols; ++x) {
        w[x] = static_cast<float>(o[x]) * (1.0f / 255.0f);
        for (int k = 0; k < 3; ++k)
          wd[x][k] = std::clamp(static_cast<float>(d[x][k]) - e[x][k], -clip, clip) * w[x];
      }
    }
  });
  cv::Mat small, smallW;
  cv::resize(weighted, small, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::resize(weight, smallW, small.size(), 0, 0, cv::INTER_AREA);
  const double sigma = std::max(1.0, sigmaPx / 2);
  cv::GaussianBlur(small, small, cv::Size(), sigma);
  cv::GaussianBlur(smallW, smallW, cv::Size(), sigma);
  smallW = cv::max(smallW, 1e-3f);
  cv::Mat ch[3];
  cv::split(small, ch);
  for (cv::Mat& c : ch)
    cv::divide(c, smallW, c);
  cv::Mat1f size;
  cv::magnitude(ch[1], ch[2], size);
  size += 0.5f * cv::abs(ch[0]);
  cv::Mat1f out;
  cv::resize(size, out, labE.size(), 0, 0, cv::INTER_LINEAR);
  return out;
}

// Median + k robust sigmas (1.4826 x the median absolute deviation) of `values`.
double noiseThreshold(std::vector<float> values, double k) {
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  const double median = *mid;
  for (float& v : values)
    v = static_cast<float>(std::abs(v - median));
  std::nth_element(values.begin(), mid, values.end());
  return median + k * 1.4826 * *mid;
}

// Per-pixel size of the Lab difference (a,b magnitude plus half of L). On `tolerant` pixels (the
// form's outline) it is the smallest over the bare frame's 3x3 neighbourhood: an edge that only
// moved by a sub-pixel camera shake is unchanged, a garment over it is not.
cv::Mat1f labDifference(const cv::Mat& labE, const cv::Mat& labD, const cv::Mat& tolerant) {
  auto size = [](const cv::Vec3b& e, const cv::Vec3b& d) {
    const float l = std::abs(static_cast<float>(e[0]) - d[0]);
    const float a = static_cast<float>(e[1]) - d[1], b = static_cast<float>(e[2]) - d[2];
    return std::sqrt(a * a + b * b) + 0.5f * l;
  };
  cv::Mat1f out(labE.size());
  cv::parallel_for_(cv::Range(0, labE.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* e = labE.ptr<cv::Vec3b>(y);
      const cv::Vec3b* d = labD.ptr<cv::Vec3b>(y);
      const uchar* t = tolerant.ptr(y);
      float* o = out.ptr<float>(y);
      const bool inner = y > 0 && y + 1 < labE.rows;
      for (int x = 0; x < labE.cols; ++x) {
        o[x] = size(e[x], d[x]);
        if (!t[x] || !inner || x == 0 || x + 1 == labE.cols)
          continue;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            o[x] = std::min(o[x], size(labE.at<cv::Vec3b>(y + dy, x + dx), d[x]));
      }
    }
  });
  return out;
}

// Where both keys see the screen, how the dressed frame differs from the bare one beyond sensor
// noise, from per-channel log ratios after a 0.15 cm blur: `changed` by the largest of them,
// `recoloured` by their spread. A shadow dims all three channels alike, so only a garment
// recolours the screen. Most of the screen is unchanged, so the noise floors are read over all
// of `where`.
struct ScreenChange {
  cv::Mat changed, recoloured;
};

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

// Form pixels that look like the bare form in shadow: darker in the dressed frame, with little
// change of chroma for the change of lightness. The garment throws its shadow on the form below
// its hem (a band on the thighs under a top, on the shins under a skirt, in the gap between the
// legs) and that band is no garment; a garment over the form changes its colour as well, unless
// it is a dark neutral one, where GrabCut's colour models (not this test) decide. Both Lab
// frames are averaged over about 0.2 cm first (sensor noise).
cv::Mat shadowOnForm(const cv::Mat& labE, const cv::Mat& labD, const cv::Mat& form,
                     double pxPerCm) {
  const double sigma = std::max(0.8, kShadowBlurCm * pxPerCm);
  cv::Mat e, d;
  cv::GaussianBlur(labE, e, cv::Size(), sigma);
  cv::GaussianBlur(labD, d, cv::Size(), sigma);
  cv::Mat out(labE.size(), CV_8UC1, cv::Scalar(0));
  cv::parallel_for_(cv::Range(0, labE.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* pe = e.ptr<cv::Vec3b>(y);
      const cv::Vec3b* pd = d.ptr<cv::Vec3b>(y);
      const uchar* f = form.ptr(y);
      uchar* o = out.ptr(y);
      for (int x = 0; x < labE.cols; ++x) {
        if (!f[x])
          continue;
        const float dl = static_cast<float>(pd[x][0]) - pe[x][0];
        const float da = static_cast<float>(pd[x][1]) - pe[x][1];
        const float db = static_cast<float>(pd[x][2]) - pe[x][2];
        const float dab = std::sqrt(da * da + db * db);
        o[x] = dl <= -kShadowMinDarkening && dab <= kShadowChromaPerLightness * -dl + kShadowChroma
                   ? 255
                   : 0;
      }
    }
  });
  return out;
}

void drawOverlay(cv::Mat& overlay, const cv::Mat& garmentMask, const GarmentMeasurement& m,
                 const calib::Calibration& cal) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(garmentMask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  const int thick = std::max(1, overlay.cols / 600);
  cv::drawContours(overlay, contours, -1, cv::Scalar(0, 255, 255), thick);
  for (const auto& [name, p] : cal.landmarks)
    cv::circle(overlay, cv::Point2d(p.x(), p.y()), 2 * thick, cv::Scalar(255, 128, 0), cv::FILLED);
  for (const auto& lm : m.landmarks) {
    cv::circle(overlay, lm.px, 3 * thick, cv::Scalar(0, 0, 255), cv::FILLED);
    cv::putText(overlay, lm.name, lm.px + cv::Point2d(4 * thick, 0), cv::FONT_HERSHEY_SIMPLEX,
                0.35 * thick, cv::Scalar(0, 0, 255), thick);
  }
}

}  // namespace

void keepFrameMemoryMapped() {
  // Frames above the default 32 MB limit would each get their own mapping, given back on free;
  // and the heap's top would be trimmed after every capture.
  mallopt(M_MMAP_THRESHOLD, 512 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
}

nlohmann::json CaptureResult::toJson() const {
  nlohmann::json j;
  j["type"] = type;
  j["attributes"] = attributes;
  j["confidence"] = confidence;
  j["runner_up"] = runnerUp;
  j["units"] = "cm";
  j["measurements"] = measurements;
  j["uncertainty_cm"] = uncertaintyCm;
  j["warnings"] = warnings;
  if (!corrections.empty())
    j["corrections"] = corrections;
  nlohmann::json t = nlohmann::json::object();
  double total = 0;
  for (const auto& s : timings) {
    t[s.stage] = s.ms;
    total += s.ms;
  }
  t["total"] = total;
  j["timings_ms"] = t;
  return j;
}

CaptureResult runCapture(const cv::Mat& emptyBgr, const cv::Mat& dressedRaw,
                         const nlohmann::json& calibration, const CaptureOptions& options) {
  CaptureResult result;
  StageTimer timer(result.timings, options.onStageDone);
  if (emptyBgr.empty() || emptyBgr.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput,
                       "the bare-form frame is empty or not an 8-bit colour image");
  if (dressedRaw.empty() || dressedRaw.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput,
                       "the dressed frame is empty or not an 8-bit colour image");
  if (emptyBgr.size() != dressedRaw.size())
    throw CaptureError(Reason::kBadInput,
                       "the dressed frame is " + std::to_string(dressedRaw.cols) + "x" +
                           std::to_string(dressedRaw.rows) + " but the bare-form frame is " +
                           std::to_string(emptyBgr.cols) + "x" + std::to_string(emptyBgr.rows));
  std::shared_ptr<const CaptureContext> ctx;
  try {
    ctx = cachedCaptureContext(calibration);
  } catch (const CaptureError&) {
    throw;
  } catch (const std::exception& e) {
    throw CaptureError(Reason::kBadInput, std::string("calibration: ") + e.what());
  }
  const calib::Calibration& cal = ctx->calibration;
  const FormView& view = *ctx->view;
  const double s = cal.pose.pxPerCm;
  if (emptyBgr.size() != cal.imageSize)
    throw CaptureError(Reason::kBadInput, "the frames are " + std::to_string(emptyBgr.cols) + "x" +
                                              std::to_string(emptyBgr.rows) +
                                              " but the calibration is for " +
                                              std::to_string(cal.imageSize.width) + "x" +
                                              std::to_string(cal.imageSize.height));
  timer.done("context");

  // Segmentation runs on copies of about options.workMegapixels; only the garment's outline against
  // the screen is placed at full resolution again (below), where the key is exact to the pixel. At
  // 12 MP this keeps every whole-frame operation on ~1 MP.
  const double ws = std::min(
      1.0, std::sqrt(options.workMegapixels * 1e6 / static_cast<double>(emptyBgr.total())));
  const double sw = s * ws;  // work-frame px per cm
  auto toWork = [&](const cv::Mat& full) {
    if (ws >= 1.0)
      return full;
    cv::Mat small;
    cv::resize(full, small, cv::Size(), ws, ws, cv::INTER_AREA);
    return small;
  };
  const Eigen::Vector2d centreW = cal.pose.offsetPx * ws;

  // 1. Remove the camera roll so that image rows are form heights (work frames here; the full
  // dressed frame below, in one warp with any re-registration shift). The bare frame's work
  // copy, edges and key come from the cache when it is the same frame as last time.
  // The motion's bands, where no garment reaches: the head above the neck and the feet.
  const int topBandEndRow = static_cast<int>(view.rowOfHeight(view.neckSideCm() + 2.0) * ws);
  // The dressed frame undistorted with the calibration's camera model, as the bare frame was
  // before registration (and is inside prepareBareFrame): both then share the registered
  // geometry, and the form's and the garment's outlines are where the projection puts them.
  const cv::Mat dressedBgr = ctx->undistorter ? ctx->undistorter->apply(dressedRaw) : dressedRaw;
  cv::Mat dressed = toWork(dressedBgr);
  // When the frame cuts the form's legs the bottom rows may hold a skirt's hem or a dress: no
  // band there, and the motion is read as a shift only.
  const int bottomBandStartRow =
      cal.frameBottomCm ? dressed.rows : static_cast<int>(dressed.rows * 0.85);
  const std::shared_ptr<const BareFrame> bare =
      prepareBareFrame(emptyBgr, cal.camera ? &*cal.camera : nullptr, ctx->undistorter.get(), ws,
                       centreW, cal.pose.rollRad, topBandEndRow, bottomBandStartRow);
  if (std::abs(cal.pose.rollRad) > 1e-6)
    dressed = rotateAbout(dressed, centreW, cal.pose.rollRad, cv::INTER_LINEAR);

  dressed = denoised(dressed);

  // 2. Key both frames; check the camera and form have not moved.
  // The shift comes first: a moved camera can also push the form against the frame's edge, and
  // "the camera moved" is the reason staff can act on.
  const FrameMotion motion = bare->motion->motionOf(dressed);
  const double shiftPx = motion.largestPx(0.5 * dressed.rows) / ws;  // full-frame px
  if (shiftPx > kMaxShiftCm * s)
    throw CaptureError(Reason::kCameraMoved,
                       "the camera or the form moved by " + fmt1(shiftPx) + " px (" +
                           fmt1(shiftPx / s) +
                           " cm) since the bare-form frame; capture the bare form again");
  const bool reregister = shiftPx > kMinShiftPx;
  if (reregister) {
    const cv::Matx33d back = motion.registration(dressed.size(), 1.0);
    cv::warpAffine(dressed, dressed, cv::Mat(back).rowRange(0, 2), dressed.size(), cv::INTER_LINEAR,
                   cv::BORDER_REPLICATE);
    result.warnings.push_back("re-registered a camera shift of " + fmt1(shiftPx) + " px");
  }
  // The full dressed frame, upright and registered: one warp, and none when neither applies.
  auto dressedFullJob = std::async(std::launch::async, [&] {
    if (std::abs(cal.pose.rollRad) <= 1e-6 && !reregister)
      return dressedBgr;
    const cv::Point2f c(static_cast<float>(cal.pose.offsetPx.x()),
                        static_cast<float>(cal.pose.offsetPx.y()));
    const cv::Mat r = cv::getRotationMatrix2D(c, -cal.pose.rollRad * 180.0 / M_PI, 1.0);
    cv::Matx33d m(r.at<double>(0, 0), r.at<double>(0, 1), r.at<double>(0, 2), r.at<double>(1, 0),
                  r.at<double>(1, 1), r.at<double>(1, 2), 0, 0, 1);
    if (reregister)
      m = motion.registration(dressed.size(), 1.0 / ws) * m;
    cv::Mat out;
    cv::warpAffine(dressedBgr, out, cv::Mat(m).rowRange(0, 2), dressedBgr.size(), cv::INTER_LINEAR,
                   cv::BORDER_REPLICATE);
    return out;
  });
  // The two keys are independent: the dressed one runs beside the (usually cached) bare one.
  auto dressedKey = std::async(std::launch::async, [&] { return key(dressed, "dressed frame"); });
  const calib::KeyResult& keyE = bare->key;
  const calib::KeyResult keyD = dressedKey.get();
  timer.done("registration");

  // 3. Masks (seed §5.2.2): the form (bare frame), the form still exposed in the dressed frame
  // (looks as it did), and the base mask of the garment, turned into a GrabCut trimap.
  cv::Mat labE, labD;
  {
    // Both frames despilled over the same pixels, or the despill itself reads as a difference
    // where one key missed part of the form (a dark green garment can cut the arms off the dressed
    // key's main piece).
    cv::Mat1b both;
    const int band = calib::KeyOptions{}.edgeBandPx;
    cv::dilate(keyE.mask | keyD.mask, both,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * band + 1, 2 * band + 1)));
    cv::Mat3b e = keyE.despilled.clone(), d = keyD.despilled.clone();
    calib::despill(e, both);
    calib::despill(d, both);
    cv::cvtColor(e, labE, cv::COLOR_BGR2Lab);
    cv::cvtColor(d, labD, cv::COLOR_BGR2Lab);
  }
  const cv::Mat formMask = keyE.mask;
  const int edgeR = std::max(1, static_cast<int>(std::lround(0.25 * sw)));
  cv::Mat formInside;
  cv::erode(formMask, formInside,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * edgeR + 1, 2 * edgeR + 1)));
  cv::Mat formOutline;
  cv::dilate(formMask, formOutline, cv::Mat(), cv::Point(-1, -1), 2);
  formOutline &= ~formInside;
  cv::Mat1f diff = labDifference(labE, labD, formOutline);
  {
    // Sensor noise differs between the two shots; average it away before thresholding, over the
    // form only (the garment's shadow changes the screen beside it).
    const int k = 2 * std::max(2, static_cast<int>(std::lround(0.3 * sw))) + 1;
    cv::Mat1f w, dw;
    formMask.convertTo(w, CV_32F, 1.0 / 255.0);
    cv::GaussianBlur(diff.mul(w), dw, cv::Size(k, k), 0);
    cv::GaussianBlur(w, w, cv::Size(k, k), 0);
    diff = dw / cv::max(w, 1e-3f);
  }
  // The form cannot vanish: inside it the dressed frame shows the form or the garment, whatever
  // the key says (a dark green garment keys as screen by its greenness). Its outline is left to
  // the key: mixed edge pixels differ between the shots by any sub-pixel shift.
  const cv::Mat fgD = keyD.mask | formInside;
  // Where the form is still visible the difference is noise; where the garment covers it, it is
  // the garment's contrast. The noise floor is read where no garment goes: the form above its
  // neck (head or neck cap). A pixel is exposed when its difference is within that noise, so a
  // garment the colour of the form still stands out by its folds and weave; Otsu's threshold
  // over the form is only the fallback for a form with too little above its neck.
  double tau = 10.0;
  const int neckRow =
      static_cast<int>(view.rowOfHeight(view.neckSideCm() + kNoiseAboveNeckCm) * ws);
  auto aboveNeck = [&](const cv::Mat1f& values) {
    std::vector<float> out;
    for (int y = 0; y < std::min(neckRow, values.rows); ++y)
      for (int x = 0; x < values.cols; x += 2)
        if (formMask.at<uchar>(y, x) && fgD.at<uchar>(y, x))
          out.push_back(values(y, x));
    return out;
  };
  const std::vector<float> noise = aboveNeck(diff);
  const bool noiseKnown = noise.size() > 2000;
  if (noiseKnown) {
    tau = std::clamp(noiseThreshold(noise, kNoiseSigmas), 2.0, 25.0);
  } else {
    cv::Mat d8;
    diff.convertTo(d8, CV_8U, 4.0);
    std::vector<uchar> values;
    for (int y = 0; y < d8.rows; y += 2)
      for (int x = 0; x < d8.cols; x += 2)
        if (formMask.at<uchar>(y, x) && fgD.at<uchar>(y, x))
          values.push_back(d8.at<uchar>(y, x));
    if (values.size() > 100) {
      cv::Mat v(values, false);
      cv::Mat dummy;
      tau = std::clamp(cv::threshold(v, dummy, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / 4.0,
                       5.0, 25.0);
    }
  }
  const int r = std::max(2, static_cast<int>(std::lround(0.4 * sw)));
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  // The form's outline counts as form out to where either key may place it (the two keys' edges
  // differ by a pixel with noise); there the difference is the shift-tolerant one.
  const cv::Mat formOrOutline = formMask | formOutline;
  cv::Mat exposed = (diff < static_cast<float>(tau)) & formOrOutline & fgD;
  // Exposed well inside the noise (half the threshold, on both tests): the form for certain, up
  // to the blur's reach from the garment.
  cv::Mat clearlyExposed = (diff < static_cast<float>(kClearlyExposed * tau)) & exposed;
  if (noiseKnown) {
    // Of what looks exposed pixel by pixel, keep only what also matches over about a centimetre:
    // a garment the colour of the form differs there.
    const cv::Mat1f averaged = averagedDifference(
        labE, labD, formInside, kAveragedDifferenceCm * sw, static_cast<float>(tau));
    const double tauAveraged = std::max(0.3, noiseThreshold(aboveNeck(averaged), kNoiseSigmas));
    exposed &= averaged < static_cast<float>(tauAveraged);
    clearlyExposed &= averaged < static_cast<float>(kClearlyExposed * tauAveraged);
  }
  cv::morphologyEx(exposed, exposed, cv::MORPH_CLOSE, kernel);
  exposed &= formOrOutline & fgD;
  // The garment's shadow on the form is not sure garment: it is GrabCut's to decide (below). A
  // shadow is a smooth band that fades into the exposed form beside the garment: what looks like
  // shadow is opened (a stripe or print of the garment shaded darker than the form is thin) and
  // kept only where it touches the exposed form. When most of what changed over the form still
  // looks like shadow, the garment itself is dark and neutral, and the test is not used.
  cv::Mat shadow = shadowOnForm(labE, labD, formInside, sw) & fgD & ~exposed;
  {
    const int rs = std::max(1, static_cast<int>(std::lround(kShadowMinWidthCm * sw / 2)));
    cv::morphologyEx(
        shadow, shadow, cv::MORPH_OPEN,
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * rs + 1, 2 * rs + 1)));
    cv::Mat touching;
    cv::dilate(exposed, touching, cv::Mat(), cv::Point(-1, -1), 2);
    cv::Mat labels;
    const int n = cv::connectedComponents(shadow, labels, 8, CV_32S);
    std::vector<uchar> keep(static_cast<std::size_t>(n), 0);
    for (int y = 0; y < labels.rows; ++y) {
      const int* l = labels.ptr<int>(y);
      const uchar* t = touching.ptr(y);
      for (int x = 0; x < labels.cols; ++x)
        if (l[x] > 0 && t[x])
          keep[static_cast<std::size_t>(l[x])] = 1;
    }
    for (int y = 0; y < labels.rows; ++y) {
      const int* l = labels.ptr<int>(y);
      uchar* m = shadow.ptr(y);
      for (int x = 0; x < labels.cols; ++x)
        m[x] = l[x] > 0 && keep[static_cast<std::size_t>(l[x])] ? 255 : 0;
    }
    const double changedOverForm = cv::countNonZero(formInside & fgD & ~exposed);
    if (cv::countNonZero(shadow) > kShadowMaxShareOfChange * changedOverForm)
      shadow.setTo(0);
  }
  cv::Mat base = fgD & ~exposed & ~shadow;
  cv::morphologyEx(base, base, cv::MORPH_OPEN, kernel);
  cv::Mat sure;
  cv::erode(base, sure, kernel);
  if (cv::countNonZero(sure) < 0.002 * static_cast<double>(formMask.total()) + 50 * ws * ws)
    throw CaptureError(
        Reason::kNoGarment,
        "no garment found: the dressed frame shows the bare form (is the garment on the form?)");
  // A garment close to the screen's colour (dark or olive green) keys as screen where it hangs
  // over the screen, and over the form wherever it is lit well. Found over the form (above, the
  // form cannot vanish), it makes every pixel where the dressed frame differs from the bare
  // screen GrabCut's to decide: the garment, or its shadow. For other garments the key's edge
  // stands, and those pixels stay screen.
  // Counted after an opening: where the two keys place the form's outline a few pixels apart
  // (the garment's shadow shifts the dressed key's screen estimate), a thin line is left.
  cv::Mat insideKeyedScreen = formInside & ~keyD.mask;
  cv::morphologyEx(insideKeyedScreen, insideKeyedScreen, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  const double keyedAsScreenCm2 = cv::countNonZero(insideKeyedScreen) / (sw * sw);
  const bool screenColoured = keyedAsScreenCm2 > kScreenColouredCm2;
  ScreenChange screenChange{cv::Mat::zeros(fgD.size(), CV_8UC1),
                            cv::Mat::zeros(fgD.size(), CV_8UC1)};
  if (screenColoured) {
    screenChange = changedScreen(keyE.despilled, keyD.despilled, ~fgD, sw);
    // The form's mixed outline pixels change colour with any sub-pixel shift: no evidence.
    screenChange.recoloured &= ~formOutline;
    result.warnings.push_back("the garment is close to the screen's colour (" +
                              std::to_string(std::lround(keyedAsScreenCm2)) +
                              " cm2 of it over the form keys as screen); its outline was found "
                              "against the bare-form frame, check it");
  }
  // GrabCut has a choice to make only near the exposed form: elsewhere the dressed foreground is
  // garment up to the key's edge against the screen (placed again at full resolution below).
  // Probable garment farther than kSettledCm from any exposed pixel is therefore sure, which
  // leaves the band cut nothing to decide along the screen-facing outline.
  // Likewise exposed form farther than kSettledCm from any garment evidence is sure form: a
  // garment the colour of the form gives GrabCut's colour models nothing to tell them apart by,
  // and it would otherwise flood the bare torso and arms from the garment.
  cv::Mat settled, settledForm;
  {
    cv::Mat1f distToExposed, distToGarment;
    cv::distanceTransform(~(exposed | shadow), distToExposed, cv::DIST_L2, cv::DIST_MASK_3);
    settled = (distToExposed > static_cast<float>(kSettledCm * sw)) & fgD;
    cv::distanceTransform(~(fgD & ~exposed), distToGarment, cv::DIST_L2, cv::DIST_MASK_3);
    settledForm =
        ((distToGarment > static_cast<float>(kSettledCm * sw)) & exposed) |
        ((distToGarment > static_cast<float>(kClearlySettledCm * sw)) & clearlyExposed & exposed);
  }
  cv::Mat trimap(fgD.size(), CV_8UC1, cv::Scalar(cv::GC_BGD + 0));
  trimap.setTo(cv::GC_PR_BGD + 0, screenChange.changed);
  trimap.setTo(cv::GC_PR_FGD + 0, screenChange.recoloured);
  trimap.setTo(cv::GC_PR_FGD + 0, fgD);
  trimap.setTo(cv::GC_FGD + 0, settled);
  trimap.setTo(cv::GC_PR_BGD + 0, exposed | shadow);
  trimap.setTo(cv::GC_BGD + 0, settledForm);
  trimap.setTo(cv::GC_FGD + 0, sure);
  timer.done("masks");
  if (const char* dir = std::getenv("GARMCAP_DEBUG_DIR")) {
    // Intermediate masks for diagnosing segmentation: trimap labels x 80, colour difference x 4,
    // the exposed form and the two keys' masks.
    cv::imwrite(std::string(dir) + "/trimap.png", trimap * 80);
    cv::Mat d8;
    diff.convertTo(d8, CV_8U, 4.0);
    cv::imwrite(std::string(dir) + "/diff.png", d8);
    cv::imwrite(std::string(dir) + "/exposed.png", exposed);
    cv::imwrite(std::string(dir) + "/shadow.png", shadow);
    cv::imwrite(std::string(dir) + "/key_bare.png", formMask);
    cv::imwrite(std::string(dir) + "/key_dressed.png", keyD.mask);
  }

  cv::Mat garmentW = grabCutCoarseToFine(keyD.despilled, trimap);
  if (screenColoured) {
    // What GrabCut took from the changed screen must be a region, not the thin halo of blur
    // and mixed pixels around an outline the key already placed.
    const cv::Mat kernelHalo = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3));
    cv::Mat beyondKey = garmentW & ~fgD;
    cv::morphologyEx(beyondKey, beyondKey, cv::MORPH_OPEN, kernelHalo);
    garmentW = (garmentW & fgD) | beyondKey;
    // A pattern's screen-coloured squares or stripes at the outline look like the garment's own
    // shadow, and GrabCut cuts around them: notches a pattern repeat deep in the garment's sides.
    // They are closed along the vertical only (a horizontal closing would bridge the gap between
    // the legs below the crotch) and over what changed since the bare frame only (changed
    // screen, form that is not exposed).
    const int rc = std::max(2, static_cast<int>(std::lround(kPatternNotchCm * sw)));
    cv::Mat closed;
    cv::morphologyEx(garmentW, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, 2 * rc + 1)));
    garmentW |= closed & (screenChange.changed | (fgD & ~exposed));
  }
  // Keep the garment's main piece and fill its holes (prints the colour of the form).
  garmentW = largestComponent(garmentW);
  if (garmentW.empty())
    throw CaptureError(Reason::kNoGarment, "no garment found after segmentation");
  {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(garmentW.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    garmentW.setTo(0);
    cv::drawContours(garmentW, contours, -1, cv::Scalar(255), cv::FILLED);
  }

  // 4. A garment must be worn by the form: mostly over it and clear of the frame's edges.
  {
    // The frame may cut the form's legs or stand, never the garment: a hem out of view leaves a
    // length that cannot be measured (and a circumference at a hem that is not there).
    const int m = 2;
    const auto touches = [&](cv::Rect strip) { return cv::countNonZero(garmentW(strip)) > 0; };
    const int w = garmentW.cols, h = garmentW.rows;
    if (touches({0, h - m, w, m}))
      throw CaptureError(
          Reason::kOffForm,
          "the garment leaves the frame at its bottom edge" +
              (cal.frameBottomCm ? " (at " + fmt1(*cal.frameBottomCm) + " cm on the form)"
                                 : std::string()) +
              ": its hem is out of view, so its length and hem cannot be measured; move the "
              "camera back or lower it so the whole garment is in view");
    for (const auto& [name, strip] : {std::pair<const char*, cv::Rect>{"top", {0, 0, w, m}},
                                      {"left", {0, 0, m, h}},
                                      {"right", {w - m, 0, m, h}}})
      if (touches(strip))
        throw CaptureError(Reason::kOffForm, std::string("the garment is cut off by the frame's ") +
                                                 name +
                                                 " edge; move the camera back so the "
                                                 "whole garment is in view");
    const double onForm = cv::countNonZero(garmentW & formMask) /
                          std::max(1.0, static_cast<double>(cv::countNonZero(garmentW)));
    if (onForm < 0.25)
      throw CaptureError(Reason::kOffForm, "the garment hangs off the form (only " +
                                               std::to_string(static_cast<int>(onForm * 100)) +
                                               "% of it covers the form)");
  }
  const cv::Mat dressedFull = dressedFullJob.get();
  const cv::Mat garment =
      ws >= 1.0 ? garmentW : garmentAtFullResolution(dressedFull, keyD, garmentW, formMask);
  timer.done("grabcut");

  // 5. Type by silhouette against the references rendered on this form.
  const Classification cls = ctx->classifier->classify(garmentW, MatchMethod::kIou);
  result.type = cls.type;
  result.attributes = cls.attributes;
  result.confidence = cls.confidence;
  result.runnerUp = cls.runnerUp;
  // Skirt or pants: shape similarity confuses a short pair of pants with a skirt of its length
  // (and a form-coloured skirt, cut less cleanly, with pants); legs that part below the crotch
  // decide it.
  if (cls.type == "skirt" || cls.type == "pants") {
    const bool pants = partedLegsCm(garment, view) >= kPartedLegsCm;
    const std::string decided = pants ? "pants" : "skirt";
    if (decided != result.type) {
      result.warnings.push_back("type: the silhouette is closest to " + result.type + ", but it " +
                                (pants ? "parts into two legs" : "does not part into legs") +
                                "; taken for " + decided);
      result.runnerUp = result.type;
      result.type = decided;
      if (pants)
        result.attributes.erase("skirt");
      else
        result.attributes["skirt"] = "h_line";  // a_line or h_line from the hem below
    }
  }
  // Top or dress: a dress's skirt hangs across the gap between the legs below the crotch; a
  // garment that ends at the crotch is a top, however its outline compares (a top's hem near the
  // crotch, with what is left of its shadow in the gap, matched short dresses on a physical rig).
  if (result.type == "dress" && view.crotchCm() &&
      coveredBelowCrotchCm(garment, view) < kSkirtBelowCrotchCm) {
    result.warnings.push_back(
        "type: the silhouette is closest to dress, but it ends at the crotch; taken for top");
    result.runnerUp = "dress";
    result.type = "top";
    result.attributes.erase("skirt");
  }
  timer.done("type");

  GarmentMeasurement gm;
  if (result.type == "unknown") {
    result.warnings.push_back("no garment type matches this silhouette well (best IoU " +
                              fmt1(cls.bestScore) + "); review it by hand");
  } else {
    // 6. Measurements, and the attributes they decide better than shape does.
    gm = measureGarment(garment, view, result.type);
    result.measurements = gm.measurements;
    for (const auto& w : gm.warnings)
      result.warnings.push_back(w);
    if (gm.measurements.count("sleeve_length")) {
      // Shorter than a sleeveless bodice reaches down the arm on this form (plus the reading's
      // scatter) is no sleeve.
      const double sl = gm.measurements.at("sleeve_length");
      const bool sleeveless = sl < std::max(2.0, ctx->sleevelessReachCm + kSleevelessMarginCm);
      result.attributes["sleeve"] = sleeveless ? "none" : (sl < 35.0 ? "short" : "long");
      if (sleeveless)
        result.measurements["sleeve_length"] = 0.0;
    }
    for (const auto& [name, value] : result.measurements)
      if (const auto u = measurementUncertaintyCm(name))
        result.uncertaintyCm[name] = *u;
    if (options.corrections) {
      nlohmann::json applied = {{"warnings", nlohmann::json::array()}};
      applyCorrections(*options.corrections, result.type, result.measurements, applied);
      if (applied.contains("corrections"))
        result.corrections = applied["corrections"];
      for (const auto& w : applied["warnings"])
        result.warnings.push_back(w.get<std::string>());
    }
    if (gm.measurements.count("hem_circ") && gm.measurements.count("hip_circ") &&
        result.attributes.count("skirt"))
      result.attributes["skirt"] =
          gm.measurements.at("hem_circ") > gm.measurements.at("hip_circ") + 12.0 ? "a_line"
                                                                                 : "h_line";
    timer.done("measure");

    // 7. Pattern.
    try {
      result.pattern =
          draftFromGarment(result.type, result.attributes, result.measurements, ctx->body,
                           view.neckSideCm() - view.waistCm(), result.warnings);
    } catch (const std::exception& e) {
      result.warnings.push_back(std::string("no pattern: ") + e.what());
    }
    timer.done("pattern");
  }

  // 8. Images, from the garment's part of the full frame only.
  result.silhouette = garment;
  result.overlay = dressedFull.clone();
  drawOverlay(result.overlay, garment, gm, cal);
  if (options.makeProductImages || options.makeTexture) {
    const int margin = static_cast<int>(std::ceil(2.0 * s));
    cv::Rect box = cv::boundingRect(garment);
    box =
        cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) &
        cv::Rect(0, 0, garment.cols, garment.rows);
    const cv::Mat3b crop = dressedFull(box);
    const cv::Mat1b maskCrop = garment(box);
    if (options.makeProductImages) {
      const ProductImages p =
          productPhotos(crop, maskCrop, bare->uprightFull(box), keyD.screenBgr,
                        {.maxSidePx = options.productSizePx,
                         .minSidePx = std::max(dressedFull.cols, dressedFull.rows) >= kShopZoomPx
                                          ? std::min(kShopZoomPx, options.productSizePx)
                                          : 0,
                         .marginFraction = 0.06,
                         .pxPerCm = s});
      result.cutout = p.cutout;
      result.cutoutRect = p.cutoutRect + box.tl();
      result.product = p.square;
      result.productPortrait = p.portrait;
    }
    timer.done("images");
    if (options.makeTexture) {
      cv::Mat3b despilled = crop.clone();
      cv::Mat1b spill;
      cv::dilate(maskCrop, spill, cv::Mat(), cv::Point(-1, -1), 2);
      calib::despill(despilled, spill);
      const TextureResult t = extractTexture(despilled, maskCrop);
      result.texture = t.tile;
      result.attributes["fabric"] = toString(t.kind);
      timer.done("texture");
    }
  } else {
    timer.done("images");
  }
  return result;
}

}  // namespace garmcap::pipeline
