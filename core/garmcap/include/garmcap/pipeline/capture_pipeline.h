#pragma once
// GarmCap: from the bare-form frame, the dressed frame and the calibration to the garment's type,
// measurements in cm, pattern and product images (seed chapter 5). This is the entry point the
// daemon and the CLI call; the stages live in their own units.

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/measurement_correction.h"

namespace garmcap::pipeline {

/// Why a capture cannot give a result. The daemon shows `what()` to staff, so it is a sentence.
class CaptureError : public std::runtime_error {
 public:
  enum class Reason {
    kBadInput,      // wrong frame size, unreadable image, bad calibration
    kNoGarment,     // the dressed frame shows the bare form
    kOffForm,       // the garment hangs off the form or is cut off by the frame
    kCameraMoved,   // camera or form moved beyond what re-registration can absorb
    kUnknownType,   // no garment type matches well enough (never forced)
    kOtherGarment,  // the back shot shows another garment than the front (outline area differs)
  };
  CaptureError(Reason reason, const std::string& message)
      : std::runtime_error(message), reason_(reason) {}
  Reason reason() const { return reason_; }

 private:
  Reason reason_;
};

struct StageTiming {
  std::string stage;  // "registration", "masks", "grabcut", "type", "landmarks", ...
  double ms = 0;
};

struct CaptureOptions {
  bool makeProductImages = true;
  bool makeTexture = true;
  // Longest side of the product photos; they are made at the camera frame's resolution and only
  // scaled down beyond this.
  int productSizePx = 4096;
  // A soft drop shadow under the garment on the white photos (ProductImageOptions::shadow); off
  // by default, as a marketplace's pure-white main image wants.
  bool productShadow = false;
  // Frames larger than this are segmented on a downscaled copy; the outline against the screen
  // is then placed at full resolution. 2 MP keeps the 4 MP rig's errors within 0.1 cm of
  // full-resolution segmentation at a fraction of its time (docs/pipeline.md).
  double workMegapixels = 2.0;
  // Called on the pipeline's thread as each stage ends, with its name and duration, so a caller
  // can show real progress; it must not throw.
  std::function<void(const StageTiming&)> onStageDone;
  // The shop's tape corrections (measurement_correction.h), applied to the readings right after
  // they are measured, so the pattern, the size run and result.json all use the corrected values;
  // null: none. Shared, read-only: fitted once per capture by the caller.
  std::shared_ptr<const CorrectionTable> corrections;
  // The size chart that completes the form's body for drafting, when runCapture builds the
  // context itself (the one-off overload below); a PreparedCapture's context names its own.
  std::string sizeChart = kDefaultSizeChart;
  // The optional back shot: the same garment turned back to front on the form, same camera and
  // bare-form frame (calibration size, 8-bit BGR). It gives the back photos and the ghost-mannequin
  // front photo (ghost_mannequin.h); empty: none, and every other output is as without it.
  cv::Mat backFrame;
};

/// Makes the C allocator keep the freed memory of frame-sized buffers for the next one instead
/// of returning it to the kernel: a capture allocates and frees dozens of 4-36 MB images, and
/// fresh pages cost a fault each (over half the capture's time measured in a VM). The process
/// then keeps up to about its peak (~1.5 GB at 12 MP) mapped between captures. Call once at
/// start-up, before any thread starts.
void keepFrameMemoryMapped();

struct CaptureResult {
  std::string type;                               // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve: none|short|long; skirt: a_line|h_line
  double confidence = 0;                          // 0..1
  std::string runnerUp;                           // second-best type
  std::map<std::string, double> measurements;     // cm, names as in issue 6 / truth.json
  // Per measurement, how far it may be off (cm, 95 %): measurementUncertaintyCm.
  std::map<std::string, double> uncertaintyCm;
  std::vector<std::string> warnings;
  // Per corrected measurement {kind, offset_cm, scale, n, residual_cm, raw_cm} (applyCorrections);
  // empty when no correction applied.
  nlohmann::json corrections = nlohmann::json::object();
  std::vector<StageTiming> timings;
  drafts::Pattern pattern;
  cv::Mat cutout;           // BGRA, garment only, soft alpha edge, full resolution (PNG)
  cv::Rect cutoutRect;      // where the cut-out lies in the upright, registered dressed frame
  cv::Mat product;          // BGR on white, square, garment centred (the shop photo, JPEG)
  cv::Mat productPortrait;  // BGR on white, 4:5 (width:height), garment centred (JPEG)
  cv::Mat silhouette;       // CV_8U garment mask, frame size
  cv::Mat overlay;          // BGR review image with landmarks
  cv::Mat texture;          // BGR one-repeat tile or mean-colour swatch
  // With CaptureOptions::backFrame: the back photos (as cutout, product, productPortrait, from the
  // back shot), and the ghost-mannequin front photos (product and productPortrait with the inside
  // of the back in the neck opening; empty when the garment has no neck opening, said in
  // warnings); backShot: {area_ratio, neck_opening_px, ghost_px} for result.json.
  cv::Mat backCutout;
  cv::Rect backCutoutRect;
  cv::Mat backProduct;
  cv::Mat backProductPortrait;
  cv::Mat ghostProduct;
  cv::Mat ghostProductPortrait;
  nlohmann::json backShot;  // null without a back shot

  nlohmann::json toJson() const;  // result.json content (no images)
};

struct BareFrame;  // the bare-form frame as segmentation compares with it (internal)

/// What every capture after one bare-form capture shares: the calibration's context and the
/// bare-form frame undistorted, scaled to the work frame, de-rolled, keyed and ready for the
/// motion estimate (about 100 ms at 12 MP). Built once, when the bare form is captured, and owned
/// by whoever runs the captures (the daemon's processor, the CLI's rig evaluation); read-only, so
/// one may serve captures on several threads.
class PreparedCapture {
 public:
  /// Throws CaptureError kBadInput when `emptyBgr` is not an 8-bit colour frame of the
  /// calibration's size, kOffForm or kBadInput when it cannot be keyed.
  PreparedCapture(std::shared_ptr<const CaptureContext> context, const cv::Mat& emptyBgr,
                  double workMegapixels = CaptureOptions{}.workMegapixels);

  const CaptureContext& context() const { return *context_; }
  const std::shared_ptr<const CaptureContext>& sharedContext() const { return context_; }
  const BareFrame& bare() const { return *bare_; }
  /// The work frame's size the bare frame was prepared for (CaptureOptions::workMegapixels).
  double workMegapixels() const { return workMegapixels_; }

 private:
  std::shared_ptr<const CaptureContext> context_;
  std::shared_ptr<const BareFrame> bare_;
  double workMegapixels_;
};

/// Runs the whole pipeline on the dressed frame `dressedBgr` against `prepared`.
/// `options.workMegapixels` must be the one `prepared` was made for (else CaptureError
/// kBadInput); `options.sizeChart` is not used (the context names its chart).
/// Throws CaptureError with a reason; never invents a measurement.
CaptureResult runCapture(const PreparedCapture& prepared, const cv::Mat& dressedBgr,
                         const CaptureOptions& options = {});

/// One capture on its own: builds the context for `calibration` (the calibration JSON,
/// docs/formats.md; its body from `options.sizeChart`) and prepares `emptyBgr`, then runs as
/// above; the preparation's time is the "context" stage. Callers capturing several garments
/// build a PreparedCapture once instead. A calibration the pipeline cannot use is CaptureError
/// kBadInput.
CaptureResult runCapture(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                         const nlohmann::json& calibration, const CaptureOptions& options = {});

}  // namespace garmcap::pipeline
