#include "garmcap/pipeline/capture_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <future>
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

// The bare-form frame is the same for every garment captured after one bare-form capture, so
// its key is kept, found again by a hash of the pixels (a few ms at 12 MP against seconds of
// keying). Copies are returned so that no caller can change the cached masks.
calib::KeyResult keyBareForm(const cv::Mat& empty) {
  static std::mutex mutex;
  static std::size_t cachedHash = 0;
  static cv::Size cachedSize;
  static std::optional<calib::KeyResult> cached;
  const cv::Mat c = empty.isContinuous() ? empty : empty.clone();
  const std::size_t h = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(c.data), c.total() * c.elemSize()));
  auto copy = [](const calib::KeyResult& k) {
    calib::KeyResult out = k;
    out.mask = k.mask.clone();
    out.alpha = k.alpha.clone();
    out.despilled = k.despilled.clone();
    return out;
  };
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (cached && cachedHash == h && cachedSize == empty.size())
      return copy(*cached);
  }
  calib::KeyResult k = key(empty, "bare-form frame");
  std::lock_guard<std::mutex> lock(mutex);
  cachedHash = h;
  cachedSize = empty.size();
  cached = copy(k);
  return k;
}

// Shift of the dressed frame against the bare-form frame by phase correlation of the two
// frames' edge images: the parts no garment changes (screen texture, head, arms, legs, the stand)
// agree at the true shift, and phase correlation is robust to the garment, which changes only a
// part of the picture. Computed at about 0.5 MP and scaled back.
cv::Point2d estimateShift(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr) {
  const double scale = std::min(1.0, std::sqrt(0.5e6 / static_cast<double>(emptyBgr.total())));
  auto edges = [&](const cv::Mat& bgr) {
    cv::Mat g, small, gx, gy, mag;
    cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
    cv::resize(g, small, cv::Size(), scale, scale, cv::INTER_AREA);
    small.convertTo(small, CV_32F);
    cv::GaussianBlur(small, small, cv::Size(3, 3), 0);
    cv::Sobel(small, gx, CV_32F, 1, 0);
    cv::Sobel(small, gy, CV_32F, 0, 1);
    cv::magnitude(gx, gy, mag);
    return mag;
  };
  const cv::Mat a = edges(emptyBgr), b = edges(dressedBgr);
  cv::Mat window;
  cv::createHanningWindow(window, a.size(), CV_32F);
  double response = 0;
  const cv::Point2d shift = cv::phaseCorrelate(a, b, window, &response);
  return {shift.x / scale, shift.y / scale};
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

  // 1. Remove the camera roll so that image rows are form heights.
  cv::Mat empty = emptyBgr, dressed = dressedBgr;
  if (std::abs(cal.pose.rollRad) > 1e-6) {
    empty = rotateAbout(emptyBgr, cal.pose.offsetPx, cal.pose.rollRad, cv::INTER_LINEAR);
    dressed = rotateAbout(dressedBgr, cal.pose.offsetPx, cal.pose.rollRad, cv::INTER_LINEAR);
  }

  // 2. Key both frames; check the camera and form have not moved.
  // The shift comes first: a moved camera can also push the form against the frame's edge, and
  // "the camera moved" is the reason staff can act on.
  const cv::Point2d shift = estimateShift(empty, dressed);
  const double shiftPx = std::hypot(shift.x, shift.y);
  if (shiftPx > kMaxShiftCm * s)
    throw CaptureError(Reason::kCameraMoved,
                       "the camera or the form moved by " + fmt1(shiftPx) + " px (" +
                           fmt1(shiftPx / s) +
                           " cm) since the bare-form frame; capture the bare form again");
  if (shiftPx > kMinShiftPx) {
    const cv::Mat back = (cv::Mat_<double>(2, 3) << 1, 0, -shift.x, 0, 1, -shift.y);
    cv::warpAffine(dressed, dressed, back, dressed.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    result.warnings.push_back("re-registered a camera shift of " + fmt1(shiftPx) + " px");
  }
  // The two keys are independent: the dressed one runs beside the (usually cached) bare one.
  auto dressedKey = std::async(std::launch::async, [&] { return key(dressed, "dressed frame"); });
  const calib::KeyResult keyE = keyBareForm(empty);
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
    const int k = 2 * std::max(2, static_cast<int>(std::lround(0.3 * s))) + 1;
    cv::GaussianBlur(diff, diff, cv::Size(k, k), 0);
  }
  const cv::Mat formMask = keyE.mask;
  const cv::Mat fgD = keyD.mask;
  // Where the form is still visible the difference is noise; where the garment covers it, it is
  // the garment's contrast. Otsu's threshold over the form separates the two; it is kept within
  // bounds so that a garment the colour of the form is not all taken for form.
  double tau = 10.0;
  {
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
  const int r = std::max(2, static_cast<int>(std::lround(0.4 * s)));
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  cv::Mat exposed = (diff < static_cast<float>(tau)) & formMask & fgD;
  cv::morphologyEx(exposed, exposed, cv::MORPH_CLOSE, kernel);
  exposed &= formMask & fgD;
  cv::Mat base = fgD & ~exposed;
  cv::morphologyEx(base, base, cv::MORPH_OPEN, kernel);
  cv::Mat sure;
  cv::erode(base, sure, kernel);
  if (cv::countNonZero(sure) < 0.002 * static_cast<double>(formMask.total()) + 50)
    throw CaptureError(
        Reason::kNoGarment,
        "no garment found: the dressed frame shows the bare form (is the garment on the form?)");
  cv::Mat trimap(fgD.size(), CV_8UC1, cv::Scalar(cv::GC_BGD + 0));
  trimap.setTo(cv::GC_PR_FGD + 0, fgD);
  trimap.setTo(cv::GC_PR_BGD + 0, exposed);
  trimap.setTo(cv::GC_FGD + 0, sure);
  timer.done("masks");
  if (const char* dir = std::getenv("GARMCAP_DEBUG_DIR")) {
    // Intermediate masks for diagnosing segmentation: trimap labels x 80, colour difference x 4.
    cv::imwrite(std::string(dir) + "/trimap.png", trimap * 80);
    cv::Mat d8;
    diff.convertTo(d8, CV_8U, 4.0);
    cv::imwrite(std::string(dir) + "/diff.png", d8);
  }

  cv::Mat garment = grabCutCoarseToFine(keyD.despilled, trimap);
  // Keep the garment's main piece and fill its holes (prints the colour of the form).
  {
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(garment, labels, stats, centroids, 8);
    int best = 0, bestArea = 0;
    for (int i = 1; i < n; ++i)
      if (stats.at<int>(i, cv::CC_STAT_AREA) > bestArea) {
        bestArea = stats.at<int>(i, cv::CC_STAT_AREA);
        best = i;
      }
    garment = labels == best;
    if (bestArea == 0)
      throw CaptureError(Reason::kNoGarment, "no garment found after segmentation");
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(garment.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    garment.setTo(0);
    cv::drawContours(garment, contours, -1, cv::Scalar(255), cv::FILLED);
  }
  timer.done("grabcut");

  // 4. A garment must be worn by the form: mostly over it and clear of the frame's edges.
  {
    const cv::Rect inner(2, 2, garment.cols - 4, garment.rows - 4);
    cv::Mat border = garment.clone();
    border(inner).setTo(0);
    if (cv::countNonZero(border) > 0)
      throw CaptureError(Reason::kOffForm, "the garment is cut off by the frame edge");
    const double onForm = cv::countNonZero(garment & formMask) /
                          std::max(1.0, static_cast<double>(cv::countNonZero(garment)));
    if (onForm < 0.25)
      throw CaptureError(Reason::kOffForm, "the garment hangs off the form (only " +
                                               std::to_string(static_cast<int>(onForm * 100)) +
                                               "% of it covers the form)");
  }

  // 5. Type by silhouette against the references rendered on this form.
  const Classification cls = ctx->classifier->classify(garment, MatchMethod::kIou);
  result.type = cls.type;
  result.attributes = cls.attributes;
  result.confidence = cls.confidence;
  result.runnerUp = cls.runnerUp;
  timer.done("type");

  GarmentMeasurement gm;
  if (cls.type == "unknown") {
    result.warnings.push_back("no garment type matches this silhouette well (best IoU " +
                              fmt1(cls.bestScore) + "); review it by hand");
  } else {
    // 6. Measurements, and the attributes they decide better than shape does.
    gm = measureGarment(garment, view, cls.type);
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

  // 8. Images.
  result.silhouette = garment;
  result.overlay = dressed.clone();
  drawOverlay(result.overlay, garment, gm, cal);
  if (options.makeProductImages) {
    result.cutout = makeCutout(keyD.despilled, garment);
    const ProductImages p =
        makeProductImages(keyD.despilled, garment, {.sizePx = options.productSizePx});
    result.product = p.onWhite;
  }
  timer.done("images");
  if (options.makeTexture) {
    const TextureResult t = extractTexture(keyD.despilled, garment);
    result.texture = t.tile;
    result.attributes["fabric"] = toString(t.kind);
    timer.done("texture");
  }
  return result;
}

}  // namespace garmcap::pipeline
