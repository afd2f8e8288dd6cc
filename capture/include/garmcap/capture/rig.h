#pragma once
// Rigs of replayed images (ARCHITECTURE.md "Rig case"): a folder with rig.json and one folder
// per case holding empty.png, dressed.png and truth.json (plus calibration.json and scene.json
// when the simulator made it). The reader is shared by the replay camera, the rig tests and
// `garmcap rig eval`. The writer of whole rigs, `garmcap rig make`, is the simulator's
// (sim::makeRig, capture/sim/.../rig_maker.h); writeRigFrame here stores one frame.
//
// Frames may also be JPEG, empty.jpg and dressed.jpg (a superset of the contract: MJPEG/UVC
// cameras deliver JPEG, and sensor noise makes PNGs of 1 MP frames about 4 MB each). A case
// holds each frame in exactly one of the two formats.
//
// rig.json:
//   {"format": "garmcap-rig", "version": 1, "generator": "...", "form": "...",
//    "width": 960, "height": 1280, "seed": 7, "image_format": "jpg", "jpeg_quality": 92,
//    "cases": [{"id": "case_000", "dir": "case_000", "type": "dress",
//               "attributes": {"sleeve": "short", "skirt": "a_line"}, "hard": false}, ...]}
// A rig made with a size chart (`rig make --chart C`) also has "chart": C, and each case the
// "size" of C its garment was drafted for. "image_format" ("png" or "jpg") is optional; when
// given, every case's frames must be in that format. "jpeg_quality" (1..100) is informative.
//
// Errors: RigError naming the file and the reason (missing, doubled or corrupt image, unknown
// field, frames of different sizes).

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace garmcap::capture {

class RigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a case's frames are stored: PNG (lossless; the contract's empty.png/dressed.png) or
/// JPEG (empty.jpg/dressed.jpg).
enum class RigImageFormat { kPng, kJpeg };

/// "png" or "jpg": the file extension without its dot, and the name in rig.json and on the
/// command line.
const char* rigImageExtension(RigImageFormat format);

/// Parses "png" or "jpg"; throws std::invalid_argument naming the value otherwise.
RigImageFormat parseRigImageFormat(const std::string& text);

inline constexpr int kDefaultJpegQuality = 92;

/// How the writer stores frames. `jpegQuality` (1..100, libjpeg's scale) applies to kJpeg.
struct RigImageOptions {
  RigImageFormat format = RigImageFormat::kPng;
  int jpegQuality = kDefaultJpegQuality;
  /// Throws std::invalid_argument when jpegQuality is outside 1..100.
  void validate() const;
};

/// The file holding one frame of a case folder, `frame` "empty" or "dressed": <frame>.png or
/// <frame>.jpg, whichever exists. Throws RigError naming the case folder and both file names
/// when neither exists ("<dir>/empty.png: missing (nor is there empty.jpg) ...") or both do
/// ("<dir>/empty.png and empty.jpg: both present ...").
std::filesystem::path rigFramePath(const std::filesystem::path& caseDir, const std::string& frame);

/// Encodes an 8-bit BGR frame as `options` says (PNG at compression 9, or baseline JPEG at
/// options.jpegQuality) and writes it atomically to `caseDir`/<frame>.<ext>; then removes the
/// frame in the other format, if any, so the case keeps exactly one. Returns the path written.
/// Throws std::invalid_argument for a bad quality, FileError (file_io.h) when encoding or writing
/// fails.
std::filesystem::path writeRigFrame(const std::filesystem::path& caseDir, const std::string& frame,
                                    const cv::Mat& bgr, const RigImageOptions& options);

struct RigCaseInfo {
  std::string id;
  std::filesystem::path dir;  // absolute (resolved against the rig folder)
  std::string type;
  std::map<std::string, std::string> attributes;
  bool hard = false;
  std::string size;  // the size of rig.json's "chart" the garment was drafted for, else empty
};

struct Rig {
  std::filesystem::path dir;
  nlohmann::json index;  // rig.json as read
  std::vector<RigCaseInfo> cases;
  /// Case by id; throws RigError naming the rig and the id.
  const RigCaseInfo& find(const std::string& id) const;
};

/// Reads `dir`/rig.json strictly and checks that every case folder holds truth.json and each of
/// its two frames in exactly one format (rigFramePath), the one of rig.json's "image_format"
/// when it has one. Images are not decoded here (see loadRigCase).
Rig readRig(const std::filesystem::path& dir);

/// One case with its frames decoded (8-bit BGR).
struct RigCase {
  std::string id;
  std::filesystem::path dir;
  cv::Mat empty;
  cv::Mat dressed;
  nlohmann::json truth;
  nlohmann::json calibration;  // calibration.json, or truth["calibration"]; null if neither
};

/// Loads a case folder. Throws RigError as rigFramePath and loadRigImage do, or
/// "<dressed>: 960x1280 differs from <empty>: 1000x1280".
RigCase loadRigCase(const std::filesystem::path& caseDir);

/// The case as a camera framing it higher would see it: both frames keep their top `keepRows`
/// rows (the form's legs, feet or stand below them leave the frame). Rows are cut at the bottom
/// only, so the image origin and with it the camera's principal point stay where they are; the
/// frame size in the calibration ("image_size", and "camera"."image_size") and in the case's
/// camera.json, which the result carries as calibration "camera" when the calibration has none,
/// become the new size. The truth is the uncut case's: the garment's measurements do not depend
/// on the framing. Throws RigError when keepRows is not in 1..rows.
RigCase cropRigCaseBottom(const RigCase& rigCase, int keepRows);

/// Decodes one frame file (8-bit BGR). Its content must match its extension: a .png must start
/// with the PNG signature; a .jpg/.jpeg must start with FF D8 and end with FF D9 (zero padding
/// after it allowed, as UVC cameras pad): libjpeg decodes a truncated JPEG into a partly grey
/// image with only a warning, so the end marker is what tells a cut file. Throws RigError
/// "<file>: missing", "<file>: truncated JPEG (no FF D9 end marker)", "<file>: not a JPEG ...",
/// "<file>: not a readable image (corrupt or truncated)".
cv::Mat loadRigImage(const std::filesystem::path& file);

/// loadRigImage, keeping the file's bytes (which decode to the returned image) and their media
/// type ("image/png" or "image/jpeg", from the checks above; empty for any other extension).
struct EncodedRigImage {
  cv::Mat bgr;
  std::string bytes;
  std::string mediaType;
};
EncodedRigImage loadRigImageWithBytes(const std::filesystem::path& file);

}  // namespace garmcap::capture
