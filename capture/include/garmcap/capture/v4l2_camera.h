#pragma once
// V4L2 back end (USB/UVC webcams): format negotiation, MMAP streaming, MJPEG and YUYV decoding,
// poll with timeouts, exposure/white balance/focus locked through UVC controls (libcamera's UVC
// path has no white-balance control, hence this back end for USB cameras). Every device access
// goes through V4l2Device, so all of this is tested against FakeV4l2Device.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/v4l2_device.h"

namespace garmcap::capture {

/// A pixel format the device offers and its frame sizes (ENUM_FMT + ENUM_FRAMESIZES).
struct V4l2FormatOption {
  std::uint32_t fourcc = 0;
  std::vector<cv::Size> sizes;
};

struct V4l2FormatChoice {
  std::uint32_t fourcc = 0;
  cv::Size size;
};

/// Picks a format and size. Only MJPEG and YUYV are decodable; kAuto prefers MJPEG (YUYV is
/// bandwidth-bound at high resolutions on USB 2.0). `wanted` of {0, 0} takes the largest size;
/// otherwise the exact size, else the smallest size covering it, else the largest. Returns
/// nullopt when the device offers no decodable format (or not the one asked for).
std::optional<V4l2FormatChoice> chooseV4l2Format(const std::vector<V4l2FormatOption>& offered,
                                                 PixelFormat want, cv::Size wanted);

/// Counters for tests and the daemon's status page.
struct V4l2Stats {
  std::uint64_t framesDecoded = 0;
  std::uint64_t framesDropped = 0;  ///< broken MJPEG, error-flagged, undecodable
  std::string lastDropReason;
  std::uint64_t timeouts = 0;
};

class V4l2Camera final : public Camera {
 public:
  /// Buffers requested from the driver (it may grant fewer).
  static constexpr std::uint32_t kBufferCount = 4;

  explicit V4l2Camera(std::string path,
                      std::unique_ptr<V4l2Device> device = makeSystemV4l2Device());
  ~V4l2Camera() override;

  std::string backend() const override { return "v4l2"; }
  std::string device() const override { return path_; }
  void open() override;
  void close() noexcept override;
  bool isOpen() const override { return fd_ >= 0; }
  void configure(const CameraConfig& config) override;
  CameraConfig config() const override { return config_; }
  cv::Size stillSize() const override { return still_.size; }
  cv::Size previewSize() const override { return preview_.size; }
  void lockSettings(const CaptureSettings& settings) override;
  CaptureSettings settings() const override { return settings_; }
  std::vector<std::string> unsupportedSettings() const override { return unsupported_; }
  Frame captureStill(const StillRequest& request = {}) override;
  void startPreview() override;
  std::optional<Frame> nextPreviewFrame(std::chrono::milliseconds timeout) override;
  void stopPreview() noexcept override;
  bool previewRunning() const override { return previewWanted_; }
  bool reconnect() override;

  /// The formats the device offered at the last configure().
  const std::vector<V4l2FormatOption>& offeredFormats() const { return offered_; }
  const V4l2Stats& stats() const { return stats_; }
  /// The device's card name from QUERYCAP.
  const std::string& card() const { return card_; }

 private:
  struct Mapping {
    void* data = nullptr;
    std::size_t length = 0;
  };

  int xioctl(unsigned long request, void* arg);
  [[noreturn]] void failErrno(const std::string& what, int err);
  void requireOpen(const char* what) const;
  std::vector<V4l2FormatOption> enumerateFormats();
  void startStream(const V4l2FormatChoice& choice);
  void stopStream() noexcept;
  /// One decoded frame, or nullopt after `timeout` without a good one. Drops broken frames.
  std::optional<Frame> grab(std::chrono::milliseconds timeout, bool preview);
  std::int32_t setControl(std::uint32_t id, std::int32_t value, const char* setting);
  void applySettings();

  std::string path_;
  std::unique_ptr<V4l2Device> dev_;
  int fd_ = -1;
  std::string card_;
  CameraConfig config_;
  bool configured_ = false;
  std::vector<V4l2FormatOption> offered_;
  V4l2FormatChoice still_;
  V4l2FormatChoice preview_;
  CaptureSettings settings_;
  bool settingsApplied_ = false;
  std::vector<std::string> unsupported_;
  // Streaming state.
  bool streaming_ = false;
  V4l2FormatChoice streamFormat_;
  std::uint32_t bytesPerLine_ = 0;
  std::vector<Mapping> buffers_;
  bool previewWanted_ = false;
  bool resumePreview_ = false;  // the preview ran when the device went away
  int settleLeft_ = 0;
  std::uint64_t sequence_ = 0;
  V4l2Stats stats_;
};

}  // namespace garmcap::capture
