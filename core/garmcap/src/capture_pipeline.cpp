#include "garmcap/pipeline/capture_pipeline.h"

#include <malloc.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string_view>

#include "bare_frame.h"
#include "frame_ops.h"
#include "garmcap/pipeline/capture_context.h"
#include "stage_draft.h"
#include "stage_images.h"
#include "stage_masks.h"
#include "stage_measure.h"
#include "stage_registration.h"
#include "stage_segmentation.h"
#include "stage_timer.h"
#include "stage_type.h"

namespace garmcap::pipeline {
namespace {

using Reason = CaptureError::Reason;

// The bare-form frame is the same for every garment captured after one bare-form capture, so it
// is prepared once and found again by a hash of its pixels, the camera model and the work
// geometry. Shared read-only. `camera` is the calibration's camera model, or null.
std::shared_ptr<const BareFrame> cachedBareFrame(const cv::Mat& emptyRaw, const CaptureContext& ctx,
                                                 const WorkGeometry& g) {
  static std::mutex mutex;
  static std::size_t cachedHash = 0;
  static std::shared_ptr<const BareFrame> cached;
  const calib::CameraModel* camera = ctx.calibration.camera ? &*ctx.calibration.camera : nullptr;
  const cv::Mat c = emptyRaw.isContinuous() ? emptyRaw : emptyRaw.clone();
  std::size_t h = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(c.data), c.total() * c.elemSize()));
  std::vector<double> keyed = {g.scale,
                               g.centre.x(),
                               g.centre.y(),
                               ctx.calibration.pose.rollRad,
                               static_cast<double>(c.cols),
                               static_cast<double>(c.rows),
                               static_cast<double>(g.topBandEndRow),
                               static_cast<double>(g.bottomBandStartRow),
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
  auto bare = std::make_shared<const BareFrame>(prepareBareFrame(emptyRaw, ctx, g));
  std::lock_guard<std::mutex> lock(mutex);
  cachedHash = h;
  cached = bare;
  return bare;
}

void checkFrames(const cv::Mat& emptyBgr, const cv::Mat& dressedRaw) {
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
}

std::shared_ptr<const CaptureContext> contextFor(const nlohmann::json& calibration,
                                                 const cv::Size& frameSize) {
  std::shared_ptr<const CaptureContext> ctx;
  try {
    ctx = cachedCaptureContext(calibration);
  } catch (const CaptureError&) {
    throw;
  } catch (const std::exception& e) {
    throw CaptureError(Reason::kBadInput, std::string("calibration: ") + e.what());
  }
  const cv::Size& calibrated = ctx->calibration.imageSize;
  if (frameSize != calibrated)
    throw CaptureError(Reason::kBadInput, "the frames are " + std::to_string(frameSize.width) +
                                              "x" + std::to_string(frameSize.height) +
                                              " but the calibration is for " +
                                              std::to_string(calibrated.width) + "x" +
                                              std::to_string(calibrated.height));
  return ctx;
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
  checkFrames(emptyBgr, dressedRaw);
  const std::shared_ptr<const CaptureContext> ctx = contextFor(calibration, emptyBgr.size());
  timer.done("context");

  // 1-2. Both frames undistorted, de-rolled (image rows are form heights), on the work frame;
  // the dressed one registered onto the bare one and keyed.
  const WorkGeometry g = workGeometry(*ctx, options.workMegapixels);
  const std::shared_ptr<const BareFrame> bare = cachedBareFrame(emptyBgr, *ctx, g);
  RegisteredFrame dressed = registerDressedFrame(dressedRaw, *ctx, *bare, g, result.warnings);
  timer.done("registration");

  // 3. The form, the form still exposed, the garment's shadow: GrabCut's trimap.
  const GarmentMasks masks = garmentMasks(bare->key, dressed.key, *ctx->view, g, result.warnings);
  timer.done("masks");

  // 4. The garment, worn by the form and in the frame, at full resolution.
  const cv::Mat garmentW = segmentGarment(dressed.key, masks, ctx->calibration, g);
  const cv::Mat dressedFull = dressed.full.get();
  const cv::Mat garment = garmentAtFullResolution(garmentW, dressedFull, dressed.key, masks, g);
  timer.done("grabcut");

  // 5. Type by silhouette against the references rendered on this form.
  const double bestScore = classifyGarment(*ctx, garmentW, garment, result);
  timer.done("type");

  GarmentMeasurement gm;
  if (result.type == "unknown") {
    result.warnings.push_back("no garment type matches this silhouette well (best IoU " +
                              fmt1(bestScore) + "); review it by hand");
  } else {
    // 6. Measurements, and the attributes they decide better than shape does.
    gm = measureCapturedGarment(*ctx, garment, options, result);
    timer.done("measure");
    // 7. Pattern.
    draftCapturedGarment(*ctx, result);
    timer.done("pattern");
  }

  // 8. Images, from the garment's part of the full frame only.
  makeCaptureImages(*ctx, {dressedFull, garment, gm, *bare, dressed.key.screenBgr}, options, timer,
                    result);
  return result;
}

}  // namespace garmcap::pipeline
