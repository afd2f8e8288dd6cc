#pragma once
// libcamera back end (CSI cameras on a Raspberry Pi; Debian's libcamera 0.0.3 API): one
// CameraManager per process, a StillCapture configuration for stills and a Viewfinder one for
// preview, FrameBufferAllocator buffers mapped once, requests recycled with ReuseBuffers, and
// exposure/white balance locked with AeEnable, ExposureTime, AnalogueGain, AwbEnable,
// ColourGains (and AfMode/LensPosition for focus) in the ControlList given to Camera::start.
// The code that changes between libcamera versions is in src/libcamera_compat.h only.
//
// libcamera headers stay out of this header (the library links libcamera privately); the
// device-independent parts are plain functions tested without a camera.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "garmcap/capture/camera.h"

namespace garmcap::capture {

/// The controls a CaptureSettings turns into, before they become a libcamera::ControlList.
/// std::nullopt = not sent (the pipeline's algorithm stays in charge).
struct LibcameraControlPlan {
  std::optional<bool> aeEnable;
  std::optional<std::int32_t> exposureTimeUs;
  std::optional<float> analogueGain;
  std::optional<bool> awbEnable;
  std::optional<float> redGain;
  std::optional<float> blueGain;
  std::optional<std::int32_t> afMode;  ///< 0 = AfModeManual, 2 = AfModeContinuous
  std::optional<float> lensPositionDioptres;
};

/// Locked settings become AeEnable=false + ExposureTime + AnalogueGain, AwbEnable=false +
/// ColourGains, AfMode=Manual + LensPosition (focusPosition / 100 dioptres); auto settings
/// only enable the algorithm.
LibcameraControlPlan planLibcameraControls(const CaptureSettings& settings);

/// Names (libcamera's, e.g. "ExposureTime") of the plan's controls the camera does not list in
/// Camera::controls(); `available` is that list of names.
std::vector<std::string> missingLibcameraControls(const LibcameraControlPlan& plan,
                                                  const std::vector<std::string>& available);

/// Nearest size: exact, else the smallest covering `wanted`, else the largest; {0, 0} wanted
/// takes the largest. nullopt when `sizes` is empty.
std::optional<cv::Size> chooseLibcameraSize(const std::vector<cv::Size>& sizes, cv::Size wanted);

/// One plane of a libcamera buffer as mapped memory.
struct PlaneView {
  std::span<const std::uint8_t> bytes;
};

/// Converts a libcamera frame to BGR. `format` is the PixelFormat's string ("RGB888",
/// "BGR888", "XRGB8888", "XBGR8888", "YUYV", "NV12", "YUV420", "MJPEG"); `stride` the bytes
/// per row of plane 0. Returns an empty Mat for an unknown format or short planes.
/// (libcamera names packed formats after DRM: RGB888 is B, G, R in memory = OpenCV's BGR.)
cv::Mat libcameraFrameToBgr(const std::string& format, cv::Size size, unsigned stride,
                            const std::vector<PlaneView>& planes);

/// Ids of the cameras libcamera sees now (empty without cameras). Starts the shared
/// CameraManager if needed.
std::vector<std::string> listLibcameraCameras();

class LibcameraCamera final : public Camera {
 public:
  /// `cameraId` empty = the first camera libcamera lists.
  explicit LibcameraCamera(std::string cameraId = {});
  ~LibcameraCamera() override;

  std::string backend() const override { return "libcamera"; }
  std::string device() const override;
  void open() override;
  void close() noexcept override;
  bool isOpen() const override;
  void configure(const CameraConfig& config) override;
  CameraConfig config() const override;
  cv::Size stillSize() const override;
  cv::Size previewSize() const override;
  void lockSettings(const CaptureSettings& settings) override;
  CaptureSettings settings() const override;
  std::vector<std::string> unsupportedSettings() const override;
  Frame captureStill(const StillRequest& request = {}) override;
  void startPreview() override;
  std::optional<Frame> nextPreviewFrame(std::chrono::milliseconds timeout) override;
  void stopPreview() noexcept override;
  bool previewRunning() const override;
  bool reconnect() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace garmcap::capture
