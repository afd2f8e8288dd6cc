#include "garmcap/capture/camera.h"

#include <algorithm>
#include <cctype>

#include "garmcap/capture/libcamera_camera.h"
#include "garmcap/capture/replay_camera.h"
#include "garmcap/capture/v4l2_camera.h"

namespace garmcap::capture {

const char* toString(CameraErrorKind kind) {
  switch (kind) {
    case CameraErrorKind::kNotFound:
      return "not found";
    case CameraErrorKind::kBusy:
      return "busy";
    case CameraErrorKind::kDisconnected:
      return "disconnected";
    case CameraErrorKind::kTimeout:
      return "timeout";
    case CameraErrorKind::kUnsupported:
      return "unsupported";
    case CameraErrorKind::kBadData:
      return "bad data";
    case CameraErrorKind::kNotAvailable:
      return "not available";
    case CameraErrorKind::kState:
      return "invalid state";
    case CameraErrorKind::kIo:
      return "I/O error";
  }
  return "?";
}

const char* toString(PixelFormat format) {
  switch (format) {
    case PixelFormat::kAuto:
      return "auto";
    case PixelFormat::kMjpeg:
      return "mjpeg";
    case PixelFormat::kYuyv:
      return "yuyv";
    case PixelFormat::kBgr888:
      return "bgr888";
  }
  return "?";
}

PixelFormat parsePixelFormat(const std::string& text) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (PixelFormat f :
       {PixelFormat::kAuto, PixelFormat::kMjpeg, PixelFormat::kYuyv, PixelFormat::kBgr888}) {
    if (t == toString(f)) {
      return f;
    }
  }
  throw std::invalid_argument("unknown pixel format '" + text +
                              "' (expected auto, mjpeg, yuyv or bgr888)");
}

std::vector<std::string> cameraBackends() {
  return {"libcamera", "v4l2", "replay"};
}

std::unique_ptr<Camera> makeCamera(const CameraOptions& options) {
  if (options.backend == "v4l2") {
    return std::make_unique<V4l2Camera>(options.device.empty() ? "/dev/video0" : options.device);
  }
  if (options.backend == "libcamera") {
    return std::make_unique<LibcameraCamera>(options.device);
  }
  if (options.backend == "replay") {
    if (options.device.empty()) {
      throw std::invalid_argument("replay camera: no rig folder given (device)");
    }
    auto camera =
        std::make_unique<ReplayCamera>(makeRigSceneSource(options.device), "replay", options.loop);
    camera->setLatency(options.replayLatency);
    return camera;
  }
  if (options.backend == "synthetic") {
    // The synthetic camera needs the scene simulator, which capture does not link
    // (docs/architecture.md): it is made by sim::makeCamera (capture/sim/.../synthetic_camera.h).
    throw CameraError(CameraErrorKind::kNotAvailable,
                      "synthetic camera: not made by capture::makeCamera; it is part of the "
                      "scene simulator (garmcap::sim), use sim::makeCamera "
                      "(capture/sim/.../synthetic_camera.h)");
  }
  std::string known;
  for (const auto& b : cameraBackends()) {
    known += (known.empty() ? "" : ", ") + b;
  }
  throw std::invalid_argument("unknown camera back end '" + options.backend + "' (known: " + known +
                              ")");
}

}  // namespace garmcap::capture
