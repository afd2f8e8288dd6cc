#pragma once
// The camera seen by the station: one interface, back ends chosen by name. capture makes the
// device back ends (libcamera, V4L2) and the replay of recorded rigs; the fourth, "synthetic"
// (scenes rendered on demand), belongs to the scene simulator's target and is made by
// sim::makeCamera (capture/sim/.../synthetic_camera.h), which forwards the others here.
//
//   auto cam = makeCamera({.backend = "v4l2", .device = "/dev/video0"});
//   cam->open();
//   cam->configure({.stillWidth = 1920, .stillHeight = 1080});
//   cam->lockSettings({.autoExposure = false, .exposureUs = 10000, ...});
//   Frame empty = cam->captureStill({Shot::kEmpty});
//   cam->startPreview();
//   while (auto f = cam->nextPreviewFrame(100ms)) { ... }
//
// Threads: a Camera is used from one thread at a time (the daemon's camera thread); calls block
// for at most the configured timeout. Nothing here touches an event loop.
// Errors: CameraError with a kind the caller can act on (reconnect on kDisconnected, show
// "no camera" on kNotFound) and a message that names the device.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "garmcap/capture/frame.h"

namespace garmcap::capture {

/// Why a camera call failed.
enum class CameraErrorKind {
  kNotFound,      ///< no such device / no camera at that path or id / rig folder missing
  kBusy,          ///< another process holds the device (EBUSY, libcamera acquire() failed)
  kDisconnected,  ///< the device went away while open (ENODEV, libcamera disconnected signal)
  kTimeout,       ///< no frame within the timeout
  kUnsupported,   ///< the device cannot do what was asked (format, size, control)
  kBadData,       ///< a frame or file could not be decoded (message names the file/frame)
  kNotAvailable,  ///< the back end is not compiled in or not wired yet
  kState,         ///< call out of order (capture before open, configure while streaming)
  kIo,            ///< any other system error (errno text in the message)
};

const char* toString(CameraErrorKind kind);

class CameraError : public std::runtime_error {
 public:
  CameraError(CameraErrorKind kind, const std::string& message)
      : std::runtime_error(message), kind_(kind) {}
  CameraErrorKind kind() const { return kind_; }

 private:
  CameraErrorKind kind_;
};

/// Pixel format requested from the device. kAuto lets the back end choose (V4L2: MJPEG for
/// stills when offered, else YUYV; libcamera: BGR888). Frames are always delivered as BGR.
enum class PixelFormat { kAuto, kMjpeg, kYuyv, kBgr888 };

const char* toString(PixelFormat format);
/// Parses "auto", "mjpeg", "yuyv", "bgr888" (case-insensitive); throws std::invalid_argument.
PixelFormat parsePixelFormat(const std::string& text);

/// Resolution and format. A width/height of 0 means "the largest the device offers" for stills
/// and "about 640 px wide" for preview. Back ends pick the nearest size the device supports
/// and report the actual one through Camera::stillSize()/previewSize().
struct CameraConfig {
  int stillWidth = 0;
  int stillHeight = 0;
  int previewWidth = 640;
  int previewHeight = 480;
  PixelFormat pixelFormat = PixelFormat::kAuto;
  /// How long one frame may take before CameraError(kTimeout).
  std::chrono::milliseconds timeout{2000};
  /// Frames thrown away after (re)starting a stream or changing controls, while the sensor
  /// settles (UVC cameras apply exposure a few frames late).
  int settleFrames = 3;
};

/// Exposure, gain, white balance and focus. Locked (auto* = false) so that the bare-form and
/// dressed frames are taken with identical settings and can be subtracted. Fields a device does
/// not support are ignored and reported by Camera::unsupportedSettings().
struct CaptureSettings {
  bool autoExposure = true;
  int exposureUs = 10000;     ///< used when !autoExposure (V4L2: sent in 100 µs units)
  double analogueGain = 1.0;  ///< used when !autoExposure; >= 1.0
  bool autoWhiteBalance = true;
  int whiteBalanceKelvin = 5000;  ///< V4L2 WHITE_BALANCE_TEMPERATURE, when !autoWhiteBalance
  double redGain = 1.5;           ///< libcamera ColourGains, when !autoWhiteBalance
  double blueGain = 1.5;
  bool autoFocus = true;
  int focusPosition = 0;  ///< V4L2 FOCUS_ABSOLUTE units (device-specific), when !autoFocus

  /// All auto* off: what the station uses between the bare-form and the dressed shot.
  bool locked() const { return !autoExposure && !autoWhiteBalance && !autoFocus; }
};

/// Per-still options.
struct StillRequest {
  StillRequest() = default;
  StillRequest(Shot s, std::string id = {}) : shot(s), caseId(std::move(id)) {}  // NOLINT

  Shot shot = Shot::kAny;  ///< used by replay/synthetic to choose the scene
  /// Replay/synthetic: serve this rig case instead of the current one (empty = current).
  std::string caseId;
};

class Camera {
 public:
  virtual ~Camera() = default;
  Camera() = default;
  Camera(const Camera&) = delete;
  Camera& operator=(const Camera&) = delete;

  /// "libcamera", "v4l2", "replay", "synthetic".
  virtual std::string backend() const = 0;
  /// Device path, camera id or rig folder, for messages and metadata.
  virtual std::string device() const = 0;

  /// Opens the device. Throws CameraError kNotFound ("no camera at /dev/video0"), kBusy, kIo.
  virtual void open() = 0;
  /// Stops streaming and releases the device; never throws; safe to call twice.
  virtual void close() noexcept = 0;
  virtual bool isOpen() const = 0;

  /// Sets resolution and format; stops the preview if it runs. Throws kUnsupported when no
  /// usable format exists, kState when not open.
  virtual void configure(const CameraConfig& config) = 0;
  virtual CameraConfig config() const = 0;
  /// Actual sizes after negotiation (width, height); {0, 0} before configure().
  virtual cv::Size stillSize() const = 0;
  virtual cv::Size previewSize() const = 0;

  /// Applies exposure/gain/white balance/focus; kept across reconnects and re-configures.
  virtual void lockSettings(const CaptureSettings& settings) = 0;
  virtual CaptureSettings settings() const = 0;
  /// Names of settings the device could not apply at the last lockSettings() (e.g.
  /// "whiteBalanceKelvin" on a camera without that control). Empty when all applied.
  virtual std::vector<std::string> unsupportedSettings() const = 0;

  /// Takes one full-resolution still (pauses the preview and resumes it after, if running).
  /// Throws CameraError (kTimeout, kDisconnected, kBadData, kState).
  virtual Frame captureStill(const StillRequest& request = {}) = 0;

  /// Starts the low-resolution preview stream.
  virtual void startPreview() = 0;
  /// Next preview frame, or std::nullopt when none arrived within `timeout` (not an error:
  /// the caller's loop decides). Throws kDisconnected when the device went away, kState when
  /// the preview is not running.
  virtual std::optional<Frame> nextPreviewFrame(std::chrono::milliseconds timeout) = 0;
  virtual void stopPreview() noexcept = 0;
  virtual bool previewRunning() const = 0;

  /// After kDisconnected: closes, reopens, re-applies the last config and settings (and the
  /// preview if it ran). Returns false (and leaves the camera closed) when the device is still
  /// absent; throws only for errors other than not-found/disconnected.
  virtual bool reconnect() = 0;
};

/// Options for makeCamera. Fields a back end does not use are ignored.
struct CameraOptions {
  /// "libcamera", "v4l2", "replay" (capture::makeCamera) or "synthetic" (sim::makeCamera).
  std::string backend = "v4l2";
  /// v4l2: device node ("/dev/video0"); libcamera: camera id, or empty for the first camera;
  /// replay: the rig folder (with rig.json); synthetic: output/cache folder (may be empty).
  std::string device;
  /// replay: injected per-frame latency.
  std::chrono::milliseconds replayLatency{0};
  /// replay/synthetic: loop over the rig's cases forever instead of failing after the last.
  bool loop = true;
  /// synthetic: the dress-form sidecar or mesh, and the seed of the first scene.
  std::filesystem::path formPath;
  std::uint64_t seed = 1;
  /// synthetic: size of the rendered frames (width, height).
  cv::Size syntheticSize{960, 1280};
};

/// Back-end names makeCamera accepts, in a stable order: libcamera, v4l2, replay.
/// (sim::cameraBackends() adds "synthetic".)
std::vector<std::string> cameraBackends();

/// Creates (does not open) a camera. Throws std::invalid_argument for an unknown back-end name
/// (listing the known ones), and CameraError(kNotAvailable) for "synthetic", naming
/// sim::makeCamera, which makes that one.
std::unique_ptr<Camera> makeCamera(const CameraOptions& options);

}  // namespace garmcap::capture
