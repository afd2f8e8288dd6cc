#pragma once
// The one seam between the station and the image/pattern pipeline: calibration from the bare-form
// frame, GarmCap on a dressed frame, and grading to a size run. Production code uses
// makePipelineProcessor() (calib + core/garmcap + core/dsw); unit tests inject a fake.
//
// Thread: called on the worker pool, one call at a time per job; must not touch the catalog.
// Errors: throws (pipeline::CaptureError, calib errors, std::exception); the message is shown to
// staff as the job's error, so it must be a sentence. Never invents results.

#include <functional>
#include <future>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/pipeline/image_files.h"
#include "garmcap/pipeline/measurement_correction.h"

namespace garmcap::daemon {

struct Config;

/// Stage name and overall progress 0..1; may be called from the worker thread at any rate.
using ProgressFn = std::function<void(const std::string& stage, double progress)>;

struct ProcessedCapture {
  std::string type;
  std::map<std::string, std::string> attributes;
  double confidence = 0;
  std::vector<std::string> warnings;
  std::map<std::string, double> measurementsCm;
  nlohmann::json result;                           // result.json (no images)
  std::map<std::string, nlohmann::json> patterns;  // "base" + one per graded size
  std::string baseSize;                            // nearest chart size, "" if none
  nlohmann::json sizeGuide;                        // null when grading did not run
  std::map<std::string, cv::Mat> images;           // kind -> BGR/BGRA/gray image (stored as PNG)
  /// When valid: `images` as pipeline::encodeImageSet encodes them, started by the processor as
  /// soon as the pipeline made them (beside the colours and the size run, which take one core),
  /// so the station stores these instead of encoding `images` again. get() throws what encoding
  /// threw.
  std::shared_future<std::vector<pipeline::EncodedImage>> encodedImages;
};

class CaptureProcessor {
 public:
  virtual ~CaptureProcessor() = default;
  /// Calibration JSON (docs/formats.md) from the bare-form frame.
  virtual nlohmann::json calibrate(const cv::Mat& emptyBgr, const ProgressFn& progress) = 0;
  /// GarmCap on the dressed frame against the bare-form frame, then grading. `corrections`
  /// (the shop's tape corrections, fitted by the station from the catalog; may be null) are
  /// applied to the readings before the pattern is drafted and graded.
  virtual ProcessedCapture process(
      const cv::Mat& emptyBgr, const cv::Mat& dressedBgr, const nlohmann::json& calibration,
      const ProgressFn& progress, std::shared_ptr<const pipeline::CorrectionTable> corrections) = 0;
  /// The back shot of an item already filed (the garment turned back to front on the form):
  /// GarmCap on its dressed frame with `backBgr` as the back shot. Returns only what the back
  /// shot adds: `images` holds the back photos and the ghost-mannequin front ("cutout_back",
  /// "product_back", "product_back_4x5", "product_ghost", "product_ghost_4x5"; a kind the
  /// library did not make is absent), `warnings` the back shot's own, `result` its "back_shot"
  /// object. A refused back shot throws pipeline::CaptureError with the library's sentence.
  /// The default refuses: a processor without the pipeline cannot make them.
  virtual ProcessedCapture processBack(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                                       const cv::Mat& backBgr, const nlohmann::json& calibration,
                                       const ProgressFn& progress);
};

/// How a capture's warnings start when it has no pattern (the draft failed): the rest is why.
inline constexpr const char* kNoPatternWarning = "no pattern: ";

/// Whether a pattern JSON holds no piece (no "panels", or an empty array).
bool patternIsEmpty(const nlohmann::json& pattern);

/// Stores `pattern` (pattern JSON, pattern_io.h) as the capture's "base" pattern, unless it has
/// no panel: a failed draft stores no pattern at all, so that no route ever serves an empty one.
/// The capture's warnings then say why ("no pattern: <reason>"); one is added if none does.
void storeBasePattern(ProcessedCapture& out, const nlohmann::json& pattern);

/// The production processor on calib/, core/garmcap and core/dsw.
std::unique_ptr<CaptureProcessor> makePipelineProcessor(const Config& config);

/// SKU printed on the hang tag, if one is visible in the frame. With zbar (hangTagDecoder() ==
/// "zbar"): a QR code, else an EAN-13/8, UPC-A/E (check digit verified), Code 128 or Code 39
/// barcode. Without it: OpenCV's QRCodeDetector only, which decodes nothing when OpenCV was
/// built without quirc, as Debian 12's 4.6 is. Returns "" when none is found; only
/// [A-Za-z0-9._-] payloads of 1..64 chars are accepted (anything else is not a SKU).
/// `bare`, if given (the calibration's bare-form frame, same size and type): only what differs
/// from it is scanned (hangTagScanImage).
std::string decodeHangTagSku(const cv::Mat& bgr, const cv::Mat& bare = {});
/// The grey image decodeHangTagSku scans: the frame cropped to the box around everything that is
/// not bare green screen (blocks of 8 px that are chroma-key green and smooth), grown by 32 px,
/// with the screen left inside the box made flat (each block its mean grey). Anything on or beside
/// the garment, a hang tag included, keeps its pixels. The whole frame in grey when it has no
/// screen or is small; empty when it is screen only. `region`, if given, receives the crop in the
/// frame. With `bare` (the calibration's bare-form frame, same size and type), blocks whose mean
/// colour is within 12 grey levels of the bare frame's in every channel are left out as well: the
/// form, its arms and legs. The crop is at least 1048 px a side (or the frame), as zbar's QR
/// reading depends on the image's size below that.
cv::Mat hangTagScanImage(const cv::Mat& bgr, cv::Rect* region = nullptr, const cv::Mat& bare = {});
/// zbar over exactly `grey` (8-bit, one channel), the SKU chosen as decodeHangTagSku chooses it;
/// "" without zbar. On the whole frame's grey it is the scan as it was before hangTagScanImage,
/// the reference the tests and the bench hold the region's scan to.
std::string decodeSkuInGrey(const cv::Mat& grey);
/// "zbar" or "opencv": what decodeHangTagSku reads with in this build.
std::string hangTagDecoder();

/// Expands a file-naming template: {sku}, {id}, {kind}, {type}, {size}, {date}. The result is
/// made safe as one file name ([A-Za-z0-9._-], other characters become '_'; never empty).
std::string expandNamingTemplate(const std::string& pattern,
                                 const std::map<std::string, std::string>& values);

}  // namespace garmcap::daemon
