#pragma once
// A captured image plus what the camera knew about it. Shared by every back end and by the
// daemon, which files stills and streams preview frames.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace garmcap::capture {

/// Which scene a still is meant to show. Hardware back ends ignore it (the scene is whatever is
/// in front of the lens); the replay and synthetic back ends use it to pick the frame to serve.
enum class Shot {
  kAny,      ///< whatever the back end serves next
  kEmpty,    ///< the bare dress form
  kDressed,  ///< the form wearing the garment
};

/// "any", "empty", "dressed".
const char* toString(Shot shot);

/// What the back end reports with a frame. Exposure fields are what the device says it used
/// (request metadata on libcamera, current control values on V4L2); std::nullopt when it does
/// not report them.
struct FrameMetadata {
  std::uint64_t sequence = 0;  ///< per-camera counter, increases by at least 1 per frame
  /// CLOCK_MONOTONIC time the frame was exposed (driver timestamp when there is one).
  std::chrono::nanoseconds timestamp{0};
  bool preview = false;     ///< true for preview-stream frames, false for stills
  std::string backend;      ///< "libcamera", "v4l2", "replay", "synthetic"
  std::string device;       ///< device path, camera id, or rig folder
  std::string pixelFormat;  ///< what came off the device ("MJPG", "YUYV", "BGR888", "PNG")
  std::optional<int> exposureUs;
  std::optional<double> analogueGain;
  std::optional<int> whiteBalanceKelvin;
  std::optional<double> redGain;   ///< libcamera ColourGains[0]
  std::optional<double> blueGain;  ///< libcamera ColourGains[1]
  Shot shot = Shot::kAny;          ///< what the frame shows, when the back end knows
  /// Replay/synthetic only: the rig case the frame came from and its ground truth file.
  std::string caseId;
  std::filesystem::path truthPath;
};

/// An image as 8-bit BGR (CV_8UC3), continuous, owned by the frame (never a view into a device
/// buffer that could be requeued under the caller).
struct Frame {
  cv::Mat bgr;
  FrameMetadata meta;
  /// A still as the camera delivered it, when it came encoded and `bgr` is exactly what
  /// cv::imdecode(encoded, cv::IMREAD_COLOR) gives (a V4L2 MJPEG still, a replayed rig's PNG or
  /// JPEG file served unscaled); empty otherwise (preview frames, raw formats, a scaled or
  /// rendered frame). The station stores these bytes as the still instead of encoding `bgr`
  /// again: a 12 MP PNG costs about a third of a second of CPU, and storing the camera's JPEG
  /// keeps the one the camera made rather than a second, bigger copy of its decoding.
  std::string encoded;
  /// "image/png" or "image/jpeg" when `encoded` is set, else empty.
  std::string encodedMediaType;
};

/// Refuses an empty/dressed pair whose images differ in size: the pipeline subtracts them pixel
/// by pixel, so frames from different modes or cameras must never be paired silently.
/// Throws std::invalid_argument naming both sizes and `what` (e.g. the rig case folder).
void requireSameSize(const cv::Mat& empty, const cv::Mat& dressed, const std::string& what);

}  // namespace garmcap::capture
