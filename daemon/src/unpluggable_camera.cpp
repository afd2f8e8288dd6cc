#include "garmcap/daemon/unpluggable_camera.h"

#include <thread>
#include <utility>

namespace garmcap::daemon {

UnpluggableCamera::UnpluggableCamera(std::unique_ptr<capture::Camera> inner,
                                     std::shared_ptr<std::atomic<bool>> off,
                                     std::shared_ptr<std::atomic<int>> stillDelayMs)
    : inner_(std::move(inner)), off_(std::move(off)), stillDelayMs_(std::move(stillDelayMs)) {}

void UnpluggableCamera::open() {
  check();
  inner_->open();
}

void UnpluggableCamera::configure(const capture::CameraConfig& c) {
  check();
  inner_->configure(c);
}

capture::Frame UnpluggableCamera::captureStill(const capture::StillRequest& r) {
  check();
  // The simulated exposure: an unplug during it fails the still as a real disconnect would.
  const auto until =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(stillDelayMs_->load());
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (*off_)
      throw capture::CameraError(
          capture::CameraErrorKind::kDisconnected,
          "camera " + inner_->device() + " disconnected during the still (simulated unplug)");
  }
  return inner_->captureStill(r);
}

void UnpluggableCamera::startPreview() {
  check();
  inner_->startPreview();
}

std::optional<capture::Frame> UnpluggableCamera::nextPreviewFrame(std::chrono::milliseconds t) {
  check();
  return inner_->nextPreviewFrame(t);
}

bool UnpluggableCamera::reconnect() {
  if (*off_)
    return false;
  return inner_->reconnect();
}

void UnpluggableCamera::check() const {
  if (*off_)
    throw capture::CameraError(capture::CameraErrorKind::kDisconnected,
                               "camera " + inner_->device() + " disconnected (simulated unplug)");
}

}  // namespace garmcap::daemon
