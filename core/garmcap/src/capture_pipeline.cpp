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
// Below the hip, pants part into legs for at least this long (the shortest shorts' inseam).
constexpr double kPartedLegsCm = 5.0;
// Dressed foreground this far from the exposed form is garment without asking GrabCut.
constexpr double kSettledCm = 2.0;
// The colour-difference noise floor is read on the form from this far above its side neck up.
constexpr double kNoiseAboveNeckCm = 4.0;
constexpr double kNoiseSigmas = 6.0;
constexpr double kAveragedDifferenceCm = 0.5;

class StageTimer {
 public:
  explicit StageTimer(std::vector<StageTiming>& out) : out_(out), start_(Clock::now()) {}
  void done(const std::string& stage) {
    const auto now = Clock::now();
    out_.push_back({stage, std::chrono::duration<double, std::milli>(now - start_).count()});
    start_ = now;
  }

 private:
  std::vector<StageTiming>& out_;
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

// Edge image for the shift estimate below, at about 0.5 MP.
double shiftScale(const cv::Mat& bgr) {
  return std::min(1.0, std::sqrt(0.5e6 / static_cast<double>(bgr.total())));
}

cv::Mat shiftEdges(const cv::Mat& bgr) {
  const double scale = shiftScale(bgr);
  cv::Mat g, small, gx, gy, mag;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  cv::resize(g, small, cv::Size(), scale, scale, cv::INTER_AREA);
  small.convertTo(small, CV_32F);
  cv::GaussianBlur(small, small, cv::Size(3, 3), 0);
  cv::Sobel(small, gx, CV_32F, 1, 0);
  cv::Sobel(small, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, mag);
  return mag;
}

// Shift of the dressed frame against the bare-form frame by phase correlation of the two
// frames' edge images: the parts no garment changes (screen texture, head, arms, legs, the stand)
// agree at the true shift, and phase correlation is robust to the garment, which changes only a
// part of the picture. Computed at about 0.5 MP and scaled back.
cv::Point2d estimateShift(const cv::Mat& emptyEdges, const cv::Mat& dressedBgr) {
  const double scale = shiftScale(dressedBgr);
  const cv::Mat b = shiftEdges(dressedBgr);
  cv::Mat window;
  cv::createHanningWindow(window, emptyEdges.size(), CV_32F);
  double response = 0;
  const cv::Point2d shift = cv::phaseCorrelate(emptyEdges, b, window, &response);
  return {shift.x / scale, shift.y / scale};
}

// The bare-form frame as segmentation uses it: the edge image of its de-rolled work frame, for
// the shift, and its key.
struct BareFrame {
  cv::Mat edges;
  calib::KeyResult key;
};

// The bare-form frame is the same for every garment captured after one bare-form capture, so it
// is prepared once and found again by a hash of its pixels and the work geometry (a few ms at
// 12 MP against ~100 ms of downscaling, de-rolling, edges and keying). Shared read-only.
std::shared_ptr<const BareFrame> prepareBareFrame(const cv::Mat& emptyFull, double ws,
                                                  const Eigen::Vector2d& centreW, double rollRad) {
  static std::mutex mutex;
  static std::size_t cachedHash = 0;
  static std::shared_ptr<const BareFrame> cached;
  const cv::Mat c = emptyFull.isContinuous() ? emptyFull : emptyFull.clone();
  std::size_t h = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(c.data), c.total() * c.elemSize()));
  for (const double v : {ws, centreW.x(), centreW.y(), rollRad, static_cast<double>(c.cols),
                         static_cast<double>(c.rows)})
    h ^= std::hash<double>{}(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (cached && cachedHash == h)
      return cached;
  }
  cv::Mat work = emptyFull;
  if (ws < 1.0)
    cv::resize(emptyFull, work, cv::Size(), ws, ws, cv::INTER_AREA);
  if (std::abs(rollRad) > 1e-6)
    work = rotateAbout(work, centreW, rollRad, cv::INTER_LINEAR);
  auto bare = std::make_shared<BareFrame>();
  bare->edges = shiftEdges(work);
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
  const cv::Mat inBand = (up >= 128) & fg;
  inBand.copyTo(full, band);
  return full;
}

// The Lab difference of the two frames averaged over about sigmaPx before taking its size
// (a,b magnitude plus half of L, as the fine difference): sensor noise averages out, while a
// garment the colour of the form keeps its small, steady offset and its folds. Each channel is
// clipped at `clip` first, so that a strong garment edge spreads only a thin halo.
cv::Mat1f averagedDifference(const cv::Mat& labE, const cv::Mat& labD, double sigmaPx, float clip) {
  cv::Mat e, d;
  labE.convertTo(e, CV_32F);
  labD.convertTo(d, CV_32F);
  cv::Mat signedDiff = d - e;
  signedDiff = cv::min(cv::max(signedDiff, -clip), clip);
  cv::Mat small;
  cv::resize(signedDiff, small, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::GaussianBlur(small, small, cv::Size(), std::max(1.0, sigmaPx / 2));
  cv::Mat ch[3];
  cv::split(small, ch);
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
  j["warnings"] = warnings;
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

CaptureResult runCapture(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                         const nlohmann::json& calibration, const CaptureOptions& options) {
  CaptureResult result;
  StageTimer timer(result.timings);
  if (emptyBgr.empty() || emptyBgr.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput,
                       "the bare-form frame is empty or not an 8-bit colour image");
  if (dressedBgr.empty() || dressedBgr.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput,
                       "the dressed frame is empty or not an 8-bit colour image");
  if (emptyBgr.size() != dressedBgr.size())
    throw CaptureError(Reason::kBadInput,
                       "the dressed frame is " + std::to_string(dressedBgr.cols) + "x" +
                           std::to_string(dressedBgr.rows) + " but the bare-form frame is " +
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
  const std::shared_ptr<const BareFrame> bare =
      prepareBareFrame(emptyBgr, ws, centreW, cal.pose.rollRad);
  cv::Mat dressed = toWork(dressedBgr);
  if (std::abs(cal.pose.rollRad) > 1e-6)
    dressed = rotateAbout(dressed, centreW, cal.pose.rollRad, cv::INTER_LINEAR);

  // 2. Key both frames; check the camera and form have not moved.
  // The shift comes first: a moved camera can also push the form against the frame's edge, and
  // "the camera moved" is the reason staff can act on.
  const cv::Point2d shiftW = estimateShift(bare->edges, dressed);
  const cv::Point2d shift = shiftW / ws;  // full-frame px
  const double shiftPx = std::hypot(shift.x, shift.y);
  if (shiftPx > kMaxShiftCm * s)
    throw CaptureError(Reason::kCameraMoved,
                       "the camera or the form moved by " + fmt1(shiftPx) + " px (" +
                           fmt1(shiftPx / s) +
                           " cm) since the bare-form frame; capture the bare form again");
  const bool reregister = shiftPx > kMinShiftPx;
  if (reregister) {
    const cv::Mat back = (cv::Mat_<double>(2, 3) << 1, 0, -shiftW.x, 0, 1, -shiftW.y);
    cv::warpAffine(dressed, dressed, back, dressed.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    result.warnings.push_back("re-registered a camera shift of " + fmt1(shiftPx) + " px");
  }
  // The full dressed frame, upright and registered: one warp, and none when neither applies.
  auto dressedFullJob = std::async(std::launch::async, [&] {
    if (std::abs(cal.pose.rollRad) <= 1e-6 && !reregister)
      return dressedBgr;
    const cv::Point2f c(static_cast<float>(cal.pose.offsetPx.x()),
                        static_cast<float>(cal.pose.offsetPx.y()));
    cv::Mat m = cv::getRotationMatrix2D(c, -cal.pose.rollRad * 180.0 / M_PI, 1.0);
    if (reregister) {
      m.at<double>(0, 2) -= shift.x;
      m.at<double>(1, 2) -= shift.y;
    }
    cv::Mat out;
    cv::warpAffine(dressedBgr, out, m, dressedBgr.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
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
  cv::cvtColor(keyE.despilled, labE, cv::COLOR_BGR2Lab);
  cv::cvtColor(keyD.despilled, labD, cv::COLOR_BGR2Lab);
  cv::Mat diff;
  {
    cv::Mat de;
    cv::absdiff(labE, labD, de);
    de.convertTo(de, CV_32FC3);
    cv::Mat ch[3];
    cv::split(de, ch);
    cv::magnitude(ch[1], ch[2], diff);
    diff = diff + 0.5f * ch[0];
    // Sensor noise differs between the two shots; average it away before thresholding.
    const int k = 2 * std::max(2, static_cast<int>(std::lround(0.3 * sw))) + 1;
    cv::GaussianBlur(diff, diff, cv::Size(k, k), 0);
  }
  const cv::Mat formMask = keyE.mask;
  const cv::Mat fgD = keyD.mask;
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
  cv::Mat exposed = (diff < static_cast<float>(tau)) & formMask & fgD;
  if (noiseKnown) {
    // Of what looks exposed pixel by pixel, keep only what also matches over about a centimetre:
    // a garment the colour of the form differs there.
    const cv::Mat1f averaged =
        averagedDifference(labE, labD, kAveragedDifferenceCm * sw, static_cast<float>(tau));
    const double tauAveraged = std::max(0.3, noiseThreshold(aboveNeck(averaged), kNoiseSigmas));
    exposed &= averaged < static_cast<float>(tauAveraged);
  }
  cv::morphologyEx(exposed, exposed, cv::MORPH_CLOSE, kernel);
  exposed &= formMask & fgD;
  cv::Mat base = fgD & ~exposed;
  cv::morphologyEx(base, base, cv::MORPH_OPEN, kernel);
  cv::Mat sure;
  cv::erode(base, sure, kernel);
  if (cv::countNonZero(sure) < 0.002 * static_cast<double>(formMask.total()) + 50 * ws * ws)
    throw CaptureError(
        Reason::kNoGarment,
        "no garment found: the dressed frame shows the bare form (is the garment on the form?)");
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
    cv::distanceTransform(~exposed, distToExposed, cv::DIST_L2, cv::DIST_MASK_3);
    settled = (distToExposed > static_cast<float>(kSettledCm * sw)) & fgD;
    cv::distanceTransform(~(fgD & ~exposed), distToGarment, cv::DIST_L2, cv::DIST_MASK_3);
    settledForm = (distToGarment > static_cast<float>(kSettledCm * sw)) & exposed;
  }
  cv::Mat trimap(fgD.size(), CV_8UC1, cv::Scalar(cv::GC_BGD + 0));
  trimap.setTo(cv::GC_PR_FGD + 0, fgD);
  trimap.setTo(cv::GC_FGD + 0, settled);
  trimap.setTo(cv::GC_PR_BGD + 0, exposed);
  trimap.setTo(cv::GC_BGD + 0, settledForm);
  trimap.setTo(cv::GC_FGD + 0, sure);
  timer.done("masks");
  if (const char* dir = std::getenv("GARMCAP_DEBUG_DIR")) {
    // Intermediate masks for diagnosing segmentation: trimap labels x 80, colour difference x 4.
    cv::imwrite(std::string(dir) + "/trimap.png", trimap * 80);
    cv::Mat d8;
    diff.convertTo(d8, CV_8U, 4.0);
    cv::imwrite(std::string(dir) + "/diff.png", d8);
  }

  cv::Mat garmentW = grabCutCoarseToFine(keyD.despilled, trimap);
  // Keep the garment's main piece and fill its holes (prints the colour of the form).
  {
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(garmentW, labels, stats, centroids, 8);
    int best = 0, bestArea = 0;
    for (int i = 1; i < n; ++i)
      if (stats.at<int>(i, cv::CC_STAT_AREA) > bestArea) {
        bestArea = stats.at<int>(i, cv::CC_STAT_AREA);
        best = i;
      }
    garmentW = labels == best;
    if (bestArea == 0)
      throw CaptureError(Reason::kNoGarment, "no garment found after segmentation");
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(garmentW.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    garmentW.setTo(0);
    cv::drawContours(garmentW, contours, -1, cv::Scalar(255), cv::FILLED);
  }

  // 4. A garment must be worn by the form: mostly over it and clear of the frame's edges.
  {
    const cv::Rect inner(2, 2, garmentW.cols - 4, garmentW.rows - 4);
    cv::Mat border = garmentW.clone();
    border(inner).setTo(0);
    if (cv::countNonZero(border) > 0)
      throw CaptureError(Reason::kOffForm, "the garment is cut off by the frame edge");
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
      const double sl = gm.measurements.at("sleeve_length");
      result.attributes["sleeve"] = sl < 2.0 ? "none" : (sl < 35.0 ? "short" : "long");
      if (sl < 2.0)
        result.measurements["sleeve_length"] = 0.0;
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
    cv::Mat3b crop = dressedFull(box).clone();
    const cv::Mat1b maskCrop = garment(box);
    cv::Mat1b spill;
    cv::dilate(maskCrop, spill, cv::Mat(), cv::Point(-1, -1), 2);
    calib::despill(crop, spill);
    if (options.makeProductImages) {
      result.cutout = makeCutout(crop, maskCrop);
      const ProductImages p = makeProductImages(crop, maskCrop, {.sizePx = options.productSizePx});
      result.product = p.onWhite;
    }
    timer.done("images");
    if (options.makeTexture) {
      const TextureResult t = extractTexture(crop, maskCrop);
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
