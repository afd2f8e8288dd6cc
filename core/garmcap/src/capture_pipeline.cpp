#include "garmcap/pipeline/capture_pipeline.h"

#include <malloc.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "bare_frame.h"
#include "frame_ops.h"
#include "garmcap/pipeline/capture_context.h"
#include "leg_gap.h"
#include "stage_back_shot.h"
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

void checkFrame(const cv::Mat& frame, const char* what) {
  if (frame.empty() || frame.type() != CV_8UC3)
    throw CaptureError(Reason::kBadInput,
                       std::string("the ") + what + " is empty or not an 8-bit colour image");
}

void checkFrameSize(const cv::Size& frameSize, const calib::Calibration& cal) {
  if (frameSize != cal.imageSize)
    throw CaptureError(Reason::kBadInput, "the frames are " + std::to_string(frameSize.width) +
                                              "x" + std::to_string(frameSize.height) +
                                              " but the calibration is for " +
                                              std::to_string(cal.imageSize.width) + "x" +
                                              std::to_string(cal.imageSize.height));
}

CaptureResult runPrepared(const PreparedCapture& prepared, const cv::Mat& dressedRaw,
                          const CaptureOptions& options, StageTimer::Clock::time_point start) {
  CaptureResult result;
  StageTimer timer(result.timings, options.onStageDone, start);
  checkFrame(dressedRaw, "dressed frame");
  const CaptureContext& ctx = prepared.context();
  checkFrameSize(dressedRaw.size(), ctx.calibration);
  if (options.workMegapixels != prepared.workMegapixels())
    throw CaptureError(Reason::kBadInput,
                       "the bare-form frame was prepared for a " + fmt1(prepared.workMegapixels()) +
                           " MP work frame, not " + fmt1(options.workMegapixels) + " MP");
  const BareFrame& bare = prepared.bare();
  const WorkGeometry& g = bare.geometry;
  timer.done("context");

  // 1-2. The dressed frame undistorted, de-rolled (image rows are form heights) and registered
  // onto the bare one, and keyed.
  RegisteredFrame dressed = registerDressedFrame(dressedRaw, ctx, bare, g, result.warnings);
  timer.done("registration");

  // 3. The form, the form still exposed, the garment's shadow: GrabCut's trimap.
  const GarmentMasks masks = garmentMasks(bare.key, dressed.key, *ctx.view, g, result.warnings);
  timer.done("masks");

  // 4. The garment, worn by the form and in the frame, at full resolution.
  const cv::Mat garmentW = segmentGarment(dressed.key, masks, ctx.calibration, g);
  const cv::Mat dressedFull = dressed.full.get();
  cv::Mat garment = garmentAtFullResolution(garmentW, dressedFull, dressed.key, masks, g);
  carveGapBetweenLegs(garment, dressedFull, *ctx.view, result.warnings);
  timer.done("grabcut");

  // 5. Type by silhouette against the references rendered on this form.
  const double bestScore = classifyGarment(ctx, garmentW, garment, result);
  timer.done("type");

  GarmentMeasurement gm;
  if (result.type == "unknown") {
    result.warnings.push_back("no garment type matches this silhouette well (best IoU " +
                              fmt1(bestScore) + "); review it by hand");
  } else {
    // 6. Measurements, and the attributes they decide better than shape does.
    gm = measureCapturedGarment(ctx, dressedFull, garment, options, result);
    timer.done("measure");
    // 7. Pattern.
    draftCapturedGarment(ctx, result);
    timer.done("pattern");
  }

  // 8. Images, from the garment's part of the full frame only.
  const PhotoLayer front = makeCaptureImages(
      ctx, {dressedFull, dressed.work, g.scale, garment, gm, bare, dressed.key.screenBgr}, options,
      timer, result);

  // 9. The optional back shot: back photos and the ghost-mannequin front.
  if (!options.backFrame.empty())
    makeBackShotImages(ctx, bare, options.backFrame, garment, front, options, timer, result);
  return result;
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
  if (!backShot.is_null())
    j["back_shot"] = backShot;
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

PreparedCapture::PreparedCapture(std::shared_ptr<const CaptureContext> context,
                                 const cv::Mat& emptyBgr, double workMegapixels)
    : context_(std::move(context)), workMegapixels_(workMegapixels) {
  checkFrame(emptyBgr, "bare-form frame");
  checkFrameSize(emptyBgr.size(), context_->calibration);
  bare_ = std::make_shared<const BareFrame>(
      prepareBareFrame(emptyBgr, *context_, workGeometry(*context_, workMegapixels)));
}

CaptureResult runCapture(const PreparedCapture& prepared, const cv::Mat& dressedBgr,
                         const CaptureOptions& options) {
  return runPrepared(prepared, dressedBgr, options, StageTimer::Clock::now());
}

CaptureResult runCapture(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                         const nlohmann::json& calibration, const CaptureOptions& options) {
  const auto start = StageTimer::Clock::now();
  checkFrame(emptyBgr, "bare-form frame");
  checkFrame(dressedBgr, "dressed frame");
  if (emptyBgr.size() != dressedBgr.size())
    throw CaptureError(Reason::kBadInput,
                       "the dressed frame is " + std::to_string(dressedBgr.cols) + "x" +
                           std::to_string(dressedBgr.rows) + " but the bare-form frame is " +
                           std::to_string(emptyBgr.cols) + "x" + std::to_string(emptyBgr.rows));
  std::shared_ptr<const CaptureContext> ctx;
  try {
    ctx = buildCaptureContext(calibration, options.sizeChart);
  } catch (const CaptureError&) {
    throw;
  } catch (const std::exception& e) {
    throw CaptureError(Reason::kBadInput, std::string("calibration: ") + e.what());
  }
  const PreparedCapture prepared(std::move(ctx), emptyBgr, options.workMegapixels);
  return runPrepared(prepared, dressedBgr, options, start);
}

}  // namespace garmcap::pipeline
