#pragma once
// Simulated rig only: a camera wrapper that can be "unplugged" to exercise the station's
// disconnect paths, and whose stills can be made slow (a long exposure, a driver that hangs) so
// that the camera can also disappear during a still. The flags are shared with the station,
// which flips them from the HTTP thread (`/api/sim/camera`) while the camera thread uses them.

#include <atomic>
#include <memory>

#include "garmcap/capture/camera.h"

namespace garmcap::daemon {

class UnpluggableCamera : public capture::Camera {
 public:
  UnpluggableCamera(std::unique_ptr<capture::Camera> inner, std::shared_ptr<std::atomic<bool>> off,
                    std::shared_ptr<std::atomic<int>> stillDelayMs);

  std::string backend() const override { return inner_->backend(); }
  std::string device() const override { return inner_->device(); }
  void open() override;
  void close() noexcept override { inner_->close(); }
  bool isOpen() const override { return inner_->isOpen(); }
  void configure(const capture::CameraConfig& c) override;
  capture::CameraConfig config() const override { return inner_->config(); }
  cv::Size stillSize() const override { return inner_->stillSize(); }
  cv::Size previewSize() const override { return inner_->previewSize(); }
  void lockSettings(const capture::CaptureSettings& s) override { inner_->lockSettings(s); }
  capture::CaptureSettings settings() const override { return inner_->settings(); }
  std::vector<std::string> unsupportedSettings() const override {
    return inner_->unsupportedSettings();
  }
  capture::Frame captureStill(const capture::StillRequest& r) override;
  void startPreview() override;
  std::optional<capture::Frame> nextPreviewFrame(std::chrono::milliseconds t) override;
  void stopPreview() noexcept override { inner_->stopPreview(); }
  bool previewRunning() const override { return inner_->previewRunning(); }
  bool reconnect() override;

 private:
  // Throws kDisconnected while unplugged.
  void check() const;

  std::unique_ptr<capture::Camera> inner_;
  std::shared_ptr<std::atomic<bool>> off_;
  std::shared_ptr<std::atomic<int>> stillDelayMs_;
};

}  // namespace garmcap::daemon
