#include "garmcap/capture/libcamera_camera.h"

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/control_ids.h>
#include <libcamera/controls.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/request.h>
#include <libcamera/stream.h>
#include <sys/mman.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/v4l2_decode.h"
#include "libcamera_compat.h"

namespace garmcap::capture {
namespace lc = libcamera;

// --- device-independent helpers ----------------------------------------------------------

LibcameraControlPlan planLibcameraControls(const CaptureSettings& s) {
  LibcameraControlPlan p;
  p.aeEnable = s.autoExposure;
  if (!s.autoExposure) {
    p.exposureTimeUs = s.exposureUs;
    p.analogueGain = static_cast<float>(s.analogueGain);
  }
  p.awbEnable = s.autoWhiteBalance;
  if (!s.autoWhiteBalance) {
    // ColourGains "can only be applied in a Request when the AWB is disabled" (0.0.3 docs).
    p.redGain = static_cast<float>(s.redGain);
    p.blueGain = static_cast<float>(s.blueGain);
  }
  if (!s.autoFocus) {
    p.afMode = 0;  // AfModeManual
    p.lensPositionDioptres = static_cast<float>(s.focusPosition) / 100.0f;
  }
  return p;
}

std::vector<std::string> missingLibcameraControls(const LibcameraControlPlan& plan,
                                                  const std::vector<std::string>& available) {
  std::vector<std::string> missing;
  auto need = [&](bool used, const char* name) {
    if (used && std::find(available.begin(), available.end(), name) == available.end()) {
      missing.emplace_back(name);
    }
  };
  need(plan.aeEnable.has_value(), "AeEnable");
  need(plan.exposureTimeUs.has_value(), "ExposureTime");
  need(plan.analogueGain.has_value(), "AnalogueGain");
  need(plan.awbEnable.has_value(), "AwbEnable");
  need(plan.redGain.has_value() || plan.blueGain.has_value(), "ColourGains");
  need(plan.afMode.has_value(), "AfMode");
  need(plan.lensPositionDioptres.has_value(), "LensPosition");
  return missing;
}

std::optional<cv::Size> chooseLibcameraSize(const std::vector<cv::Size>& sizes, cv::Size wanted) {
  if (sizes.empty()) {
    return std::nullopt;
  }
  auto area = [](cv::Size s) { return static_cast<long>(s.width) * s.height; };
  const cv::Size largest = *std::max_element(
      sizes.begin(), sizes.end(), [&](cv::Size a, cv::Size b) { return area(a) < area(b); });
  if (wanted.width <= 0 || wanted.height <= 0) {
    return largest;
  }
  std::optional<cv::Size> best;
  for (const auto& s : sizes) {
    if (s == wanted) {
      return s;
    }
    if (s.width >= wanted.width && s.height >= wanted.height && (!best || area(s) < area(*best))) {
      best = s;
    }
  }
  return best.value_or(largest);
}

cv::Mat libcameraFrameToBgr(const std::string& format, cv::Size size, unsigned stride,
                            const std::vector<PlaneView>& planes) {
  if (planes.empty() || size.width <= 0 || size.height <= 0) {
    return {};
  }
  const auto w = static_cast<std::size_t>(size.width);
  const auto h = static_cast<std::size_t>(size.height);
  const auto& p0 = planes[0].bytes;
  auto packed = [&](int type, std::size_t bpp, int code) -> cv::Mat {
    const std::size_t rowBytes = stride != 0 ? stride : w * bpp;
    if (rowBytes < w * bpp || p0.size() < rowBytes * (h - 1) + w * bpp) {
      return {};
    }
    const cv::Mat view(size.height, size.width, type, const_cast<std::uint8_t*>(p0.data()),
                       rowBytes);
    cv::Mat out;
    if (code < 0) {
      out = view.clone();  // the buffer goes back to the camera: own the pixels
    } else {
      cv::cvtColor(view, out, code);
    }
    return out;
  };
  if (format == "RGB888") {
    return packed(CV_8UC3, 3, -1);
  }
  if (format == "BGR888") {
    return packed(CV_8UC3, 3, cv::COLOR_RGB2BGR);
  }
  if (format == "XRGB8888" || format == "ARGB8888") {
    return packed(CV_8UC4, 4, cv::COLOR_BGRA2BGR);
  }
  if (format == "XBGR8888" || format == "ABGR8888") {
    return packed(CV_8UC4, 4, cv::COLOR_RGBA2BGR);
  }
  if (format == "YUYV") {
    return decodeYuyv(p0, size.width, size.height, static_cast<int>(stride != 0 ? stride : 2 * w));
  }
  if (format == "MJPEG") {
    return checkMjpegFrame(p0) == MjpegCheck::kOk ? decodeMjpeg(p0) : cv::Mat();
  }
  if (format == "NV12" || format == "YUV420") {
    if (size.width % 2 != 0 || size.height % 2 != 0) {
      return {};
    }
    const std::size_t ys = stride != 0 ? stride : w;
    const bool nv12 = format == "NV12";
    const std::size_t cs = nv12 ? ys : ys / 2;  // chroma stride
    const std::size_t ySize = ys * h;
    const std::size_t cSize = cs * (h / 2);
    // Planes may come separately or packed one after another in plane 0.
    std::vector<std::span<const std::uint8_t>> parts;
    if (planes.size() == 1) {
      const std::size_t need = ySize + (nv12 ? cSize : 2 * cSize);
      if (p0.size() < need) {
        return {};
      }
      parts.push_back(p0.subspan(0, ySize));
      parts.push_back(p0.subspan(ySize, cSize));
      if (!nv12) {
        parts.push_back(p0.subspan(ySize + cSize, cSize));
      }
    } else {
      for (const auto& p : planes) {
        parts.push_back(p.bytes);
      }
    }
    if (parts[0].size() < ySize || parts[1].size() < cSize ||
        (!nv12 && (parts.size() < 3 || parts[2].size() < cSize))) {
      return {};
    }
    // Repack without stride padding, the layout cvtColor expects.
    cv::Mat yuv(static_cast<int>(h + h / 2), size.width, CV_8UC1);
    for (std::size_t y = 0; y < h; ++y) {
      std::memcpy(yuv.ptr(static_cast<int>(y)), parts[0].data() + y * ys, w);
    }
    std::uint8_t* dst = yuv.ptr(static_cast<int>(h));
    const std::size_t cw = nv12 ? w : w / 2;
    for (std::size_t plane = 1; plane < (nv12 ? 2u : 3u); ++plane) {
      for (std::size_t y = 0; y < h / 2; ++y) {
        std::memcpy(dst, parts[plane].data() + y * cs, cw);
        dst += cw;
      }
    }
    cv::Mat out;
    cv::cvtColor(yuv, out, nv12 ? cv::COLOR_YUV2BGR_NV12 : cv::COLOR_YUV2BGR_I420);
    return out;
  }
  return {};
}

// --- the shared CameraManager ----------------------------------------------------------------

namespace {

/// libcamera allows one CameraManager per process; every LibcameraCamera shares it and the
/// last one to go stops it.
std::shared_ptr<lc::CameraManager> sharedCameraManager() {
  static std::mutex mutex;
  static std::weak_ptr<lc::CameraManager> weak;
  std::lock_guard lock(mutex);
  if (auto cm = weak.lock()) {
    return cm;
  }
  auto* raw = new lc::CameraManager();
  std::shared_ptr<lc::CameraManager> cm(raw, [](lc::CameraManager* m) {
    m->stop();
    delete m;
  });
  const int r = cm->start();
  if (r < 0) {
    throw CameraError(
        CameraErrorKind::kIo,
        std::string("libcamera: camera manager failed to start: ") + std::strerror(-r));
  }
  weak = cm;
  return cm;
}

std::string idList(const std::vector<std::shared_ptr<lc::Camera>>& cameras) {
  std::string s;
  for (const auto& c : cameras) {
    s += (s.empty() ? "" : ", ") + c->id();
  }
  return s.empty() ? "none" : s;
}

lc::PixelFormat libcameraFormatFor(PixelFormat f) {
  switch (f) {
    case PixelFormat::kMjpeg:
      return lc::formats::MJPEG;
    case PixelFormat::kYuyv:
      return lc::formats::YUYV;
    default:
      return lc::formats::RGB888;  // B, G, R in memory: OpenCV's BGR without conversion
  }
}

}  // namespace

std::vector<std::string> listLibcameraCameras() {
  auto cm = sharedCameraManager();
  std::vector<std::string> ids;
  for (const auto& c : cm->cameras()) {
    ids.push_back(c->id());
  }
  return ids;
}

// --- LibcameraCamera -------------------------------------------------------------------------

struct LibcameraCamera::Impl {
  std::string requestedId;
  std::shared_ptr<lc::CameraManager> cm;
  std::shared_ptr<lc::Camera> cam;
  CameraConfig config;
  bool configured = false;
  CaptureSettings settings;
  bool settingsSet = false;
  std::vector<std::string> unsupported;
  cv::Size still;
  cv::Size preview;

  // Running stream.
  std::unique_ptr<lc::CameraConfiguration> camConfig;
  std::unique_ptr<lc::FrameBufferAllocator> allocator;
  lc::Stream* stream = nullptr;
  bool running = false;
  bool runningPreview = false;
  std::string format;
  cv::Size size;
  unsigned stride = 0;
  std::vector<std::unique_ptr<lc::Request>> requests;
  std::map<const lc::FrameBuffer*, std::vector<PlaneView>> planes;
  std::vector<std::pair<void*, std::size_t>> mappings;
  bool previewWanted = false;
  bool resumePreview = false;  // the preview ran when the camera went away
  int settleLeft = 0;
  std::uint64_t sequence = 0;

  // Filled by libcamera's thread: the slots only queue and notify (never block it).
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<lc::Request*> completed;
  std::atomic<bool> disconnected{false};

  void onRequestCompleted(lc::Request* request) {
    {
      std::lock_guard lock(mutex);
      completed.push_back(request);
    }
    cv.notify_one();
  }
  void onDisconnected() {
    disconnected = true;
    cv.notify_all();
  }

  std::string name() const {
    if (cam) {
      return "libcamera camera " + cam->id();
    }
    return requestedId.empty() ? std::string("libcamera camera")
                               : "libcamera camera " + requestedId;
  }

  [[noreturn]] void fail(CameraErrorKind kind, const std::string& what) const {
    throw CameraError(kind, name() + ": " + what);
  }

  void requireOpen(const char* what) const {
    if (!cam) {
      throw CameraError(CameraErrorKind::kState,
                        std::string(what) + ": " + name() + " is not open");
    }
    if (disconnected) {
      throw CameraError(CameraErrorKind::kDisconnected, name() + " disconnected");
    }
  }

  lc::ControlList startControls() {
    lc::ControlList controls(cam->controls());
    if (!settingsSet) {
      return controls;
    }
    const LibcameraControlPlan plan = planLibcameraControls(settings);
    const auto& info = cam->controls();
    auto has = [&](const lc::ControlId& id) { return info.find(&id) != info.end(); };
    if (plan.aeEnable && has(lc::controls::AeEnable)) {
      controls.set(lc::controls::AeEnable, *plan.aeEnable);
    }
    if (plan.exposureTimeUs && has(lc::controls::ExposureTime)) {
      controls.set(lc::controls::ExposureTime, *plan.exposureTimeUs);
    }
    if (plan.analogueGain && has(lc::controls::AnalogueGain)) {
      controls.set(lc::controls::AnalogueGain, *plan.analogueGain);
    }
    if (plan.exposureTimeUs) {
      compat::addManualExposureModes(controls);
    }
    if (plan.awbEnable && has(lc::controls::AwbEnable)) {
      controls.set(lc::controls::AwbEnable, *plan.awbEnable);
    }
    if (plan.redGain && plan.blueGain && has(lc::controls::ColourGains)) {
      const std::array<float, 2> gains{*plan.redGain, *plan.blueGain};
      controls.set(lc::controls::ColourGains, lc::Span<const float, 2>(gains));
    }
    if (plan.afMode && has(lc::controls::AfMode)) {
      controls.set(lc::controls::AfMode, *plan.afMode);
    }
    if (plan.lensPositionDioptres && has(lc::controls::LensPosition)) {
      controls.set(lc::controls::LensPosition, *plan.lensPositionDioptres);
    }
    return controls;
  }

  void computeUnsupported() {
    std::vector<std::string> names;
    for (const auto& [id, info] : cam->controls()) {
      names.push_back(id->name());
    }
    const auto missing = missingLibcameraControls(planLibcameraControls(settings), names);
    // Report in CaptureSettings' vocabulary.
    static const std::map<std::string, std::string> kSetting{
        {"AeEnable", "autoExposure"},        {"ExposureTime", "exposureUs"},
        {"AnalogueGain", "analogueGain"},    {"AwbEnable", "autoWhiteBalance"},
        {"ColourGains", "redGain/blueGain"}, {"AfMode", "autoFocus"},
        {"LensPosition", "focusPosition"}};
    unsupported.clear();
    for (const auto& m : missing) {
      unsupported.push_back(kSetting.at(m));
    }
  }

  void start(bool forPreview) {
    if (running) {
      return;
    }
    const auto role = forPreview ? lc::StreamRole::Viewfinder : lc::StreamRole::StillCapture;
    camConfig = compat::generateConfiguration(*cam, role);
    if (!camConfig || camConfig->empty()) {
      fail(CameraErrorKind::kUnsupported, std::string("no configuration for the ") +
                                              (forPreview ? "viewfinder" : "still") + " role");
    }
    lc::StreamConfiguration& sc = camConfig->at(0);
    const lc::PixelFormat wantedFormat = libcameraFormatFor(config.pixelFormat);
    const auto offered = sc.formats().pixelformats();
    if (std::find(offered.begin(), offered.end(), wantedFormat) != offered.end()) {
      sc.pixelFormat = wantedFormat;
    } else if (config.pixelFormat == PixelFormat::kMjpeg ||
               config.pixelFormat == PixelFormat::kYuyv) {
      fail(CameraErrorKind::kUnsupported, "does not offer " + wantedFormat.toString());
    }
    // else: keep the pipeline's default format (e.g. YUYV/MJPEG on UVC) and convert it.
    std::vector<cv::Size> sizes;
    for (const auto& s : sc.formats().sizes(sc.pixelFormat)) {
      sizes.emplace_back(static_cast<int>(s.width), static_cast<int>(s.height));
    }
    const cv::Size wanted = forPreview ? cv::Size(config.previewWidth, config.previewHeight)
                                       : cv::Size(config.stillWidth, config.stillHeight);
    if (auto chosen = chooseLibcameraSize(sizes, wanted)) {
      sc.size =
          lc::Size(static_cast<unsigned>(chosen->width), static_cast<unsigned>(chosen->height));
    }
    compat::setIdentityOrientation(*camConfig);
    if (camConfig->validate() == lc::CameraConfiguration::Invalid) {
      fail(CameraErrorKind::kUnsupported, "configuration " + sc.toString() + " is invalid");
    }
    if (const int r = cam->configure(camConfig.get()); r < 0) {
      fail(r == -EBUSY ? CameraErrorKind::kBusy : CameraErrorKind::kIo,
           std::string("configure failed: ") + std::strerror(-r));
    }
    stream = sc.stream();
    format = sc.pixelFormat.toString();
    size = cv::Size(static_cast<int>(sc.size.width), static_cast<int>(sc.size.height));
    stride = sc.stride;
    (forPreview ? preview : still) = size;

    allocator = std::make_unique<lc::FrameBufferAllocator>(cam);
    if (allocator->allocate(stream) < 0) {
      stop();
      fail(CameraErrorKind::kIo, "cannot allocate frame buffers");
    }
    for (const auto& buffer : allocator->buffers(stream)) {
      // Planes of one buffer usually share a dmabuf fd: map each fd once, over all its planes
      // (rpicam-apps does the same).
      std::map<int, std::pair<std::uint8_t*, std::size_t>> byFd;
      for (const auto& plane : buffer->planes()) {
        auto& entry = byFd[plane.fd.get()];
        entry.second = std::max<std::size_t>(entry.second, plane.offset + plane.length);
      }
      for (auto& [fd, entry] : byFd) {
        void* p = ::mmap(nullptr, entry.second, PROT_READ, MAP_SHARED, fd, 0);
        if (p == MAP_FAILED) {
          const int err = errno;
          stop();
          fail(CameraErrorKind::kIo,
               std::string("mmap of a frame buffer failed: ") + std::strerror(err));
        }
        mappings.emplace_back(p, entry.second);
        entry.first = static_cast<std::uint8_t*>(p);
      }
      std::vector<PlaneView> views;
      for (const auto& plane : buffer->planes()) {
        views.push_back({std::span<const std::uint8_t>(byFd[plane.fd.get()].first + plane.offset,
                                                       plane.length)});
      }
      planes[buffer.get()] = std::move(views);
      std::unique_ptr<lc::Request> request = cam->createRequest();
      if (!request || request->addBuffer(stream, buffer.get()) < 0) {
        stop();
        fail(CameraErrorKind::kIo, "cannot create a capture request");
      }
      requests.push_back(std::move(request));
    }
    lc::ControlList controls = startControls();
    if (const int r = cam->start(&controls); r < 0) {
      stop();
      fail(CameraErrorKind::kIo, std::string("start failed: ") + std::strerror(-r));
    }
    running = true;
    runningPreview = forPreview;
    for (auto& request : requests) {
      if (cam->queueRequest(request.get()) < 0) {
        stop();
        fail(CameraErrorKind::kIo, "cannot queue a capture request");
      }
    }
    settleLeft = config.settleFrames;
  }

  void stop() noexcept {
    if (running && cam) {
      cam->stop();  // completes pending requests as cancelled
    }
    running = false;
    {
      std::lock_guard lock(mutex);
      completed.clear();
    }
    requests.clear();
    planes.clear();
    for (auto& [p, length] : mappings) {
      ::munmap(p, length);
    }
    mappings.clear();
    if (allocator && stream) {
      allocator->free(stream);
    }
    allocator.reset();
    stream = nullptr;
    camConfig.reset();
  }

  std::optional<Frame> grab(std::chrono::milliseconds timeout, bool forPreview) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      lc::Request* request = nullptr;
      {
        std::unique_lock lock(mutex);
        cv.wait_until(lock, deadline, [&] { return !completed.empty() || disconnected; });
        if (!disconnected && !completed.empty()) {
          request = completed.front();
          completed.pop_front();
        }
      }
      if (disconnected) {
        stop();
        fail(CameraErrorKind::kDisconnected, "disconnected");
      }
      if (request == nullptr) {
        return std::nullopt;
      }
      if (request->status() == lc::Request::RequestCancelled) {
        continue;
      }
      lc::FrameBuffer* buffer = request->findBuffer(stream);
      auto requeue = [&] {
        request->reuse(lc::Request::ReuseBuffers);
        if (cam->queueRequest(request) < 0) {
          fail(CameraErrorKind::kIo, "cannot requeue a capture request");
        }
      };
      if (buffer == nullptr || buffer->metadata().status != lc::FrameMetadata::FrameSuccess) {
        requeue();
        continue;
      }
      if (settleLeft > 0) {
        --settleLeft;
        requeue();
        continue;
      }
      std::vector<PlaneView> views = planes.at(buffer);
      const auto meta = buffer->metadata().planes();
      for (std::size_t i = 0; i < views.size() && i < meta.size(); ++i) {
        if (format == "MJPEG") {  // compressed: only bytesused are valid
          views[i].bytes = views[i].bytes.subspan(
              0, std::min<std::size_t>(meta[i].bytesused, views[i].bytes.size()));
        }
      }
      cv::Mat bgr = libcameraFrameToBgr(format, size, stride, views);
      Frame frame;
      frame.meta.sequence = sequence++;
      frame.meta.preview = forPreview;
      frame.meta.backend = "libcamera";
      frame.meta.device = cam->id();
      frame.meta.pixelFormat = format;
      frame.meta.timestamp = std::chrono::nanoseconds(buffer->metadata().timestamp);
      const lc::ControlList& md = request->metadata();
      if (auto v = md.get(lc::controls::SensorTimestamp)) {
        frame.meta.timestamp = std::chrono::nanoseconds(*v);
      }
      if (auto v = md.get(lc::controls::ExposureTime)) {
        frame.meta.exposureUs = *v;
      }
      if (auto v = md.get(lc::controls::AnalogueGain)) {
        frame.meta.analogueGain = *v;
      }
      if (auto v = md.get(lc::controls::ColourGains)) {
        frame.meta.redGain = (*v)[0];
        frame.meta.blueGain = (*v)[1];
      }
      if (auto v = md.get(lc::controls::ColourTemperature)) {
        frame.meta.whiteBalanceKelvin = *v;
      }
      requeue();
      if (bgr.empty()) {
        continue;  // undecodable (e.g. broken MJPEG from a UVC camera): dropped
      }
      frame.bgr = std::move(bgr);
      return frame;
    }
  }
};

LibcameraCamera::LibcameraCamera(std::string cameraId) : impl_(std::make_unique<Impl>()) {
  impl_->requestedId = std::move(cameraId);
}

LibcameraCamera::~LibcameraCamera() {
  close();
}

std::string LibcameraCamera::device() const {
  return impl_->cam ? impl_->cam->id() : impl_->requestedId;
}

void LibcameraCamera::open() {
  auto& d = *impl_;
  if (d.cam) {
    return;
  }
  d.cm = sharedCameraManager();
  const auto cameras = d.cm->cameras();
  std::shared_ptr<lc::Camera> cam;
  if (d.requestedId.empty()) {
    if (cameras.empty()) {
      d.cm.reset();
      throw CameraError(CameraErrorKind::kNotFound,
                        "no libcamera camera found (libcamera " + lc::CameraManager::version() +
                            " lists none; for USB webcams use the v4l2 back end)");
    }
    cam = cameras.front();
  } else {
    cam = d.cm->get(d.requestedId);
    if (!cam) {
      d.cm.reset();
      throw CameraError(
          CameraErrorKind::kNotFound,
          "no libcamera camera with id '" + d.requestedId + "' (found: " + idList(cameras) + ")");
    }
  }
  if (cam->acquire() < 0) {
    d.cm.reset();
    throw CameraError(CameraErrorKind::kBusy,
                      "libcamera camera " + cam->id() + " is busy (acquired by another user)");
  }
  d.cam = cam;
  d.disconnected = false;
  d.cam->requestCompleted.connect(&d, &Impl::onRequestCompleted);
  d.cam->disconnected.connect(&d, &Impl::onDisconnected);
  if (d.settingsSet) {
    d.computeUnsupported();
  }
}

void LibcameraCamera::close() noexcept {
  auto& d = *impl_;
  d.stop();
  d.previewWanted = false;
  d.resumePreview = false;
  if (d.cam) {
    d.cam->requestCompleted.disconnect(&d);
    d.cam->disconnected.disconnect(&d);
    d.cam->release();
    d.cam.reset();
  }
  d.cm.reset();
}

bool LibcameraCamera::isOpen() const {
  return impl_->cam != nullptr;
}

void LibcameraCamera::configure(const CameraConfig& config) {
  auto& d = *impl_;
  d.requireOpen("configure");
  if (config.stillWidth < 0 || config.stillHeight < 0 || config.previewWidth < 0 ||
      config.previewHeight < 0 || config.timeout.count() <= 0 || config.settleFrames < 0) {
    d.fail(CameraErrorKind::kUnsupported,
           "invalid configuration (negative size, settle frames or timeout)");
  }
  const bool resume = d.previewWanted;
  d.stop();
  d.config = config;
  d.configured = true;
  d.still = {config.stillWidth, config.stillHeight};
  d.preview = {config.previewWidth, config.previewHeight};
  if (resume) {
    d.start(true);
  }
}

CameraConfig LibcameraCamera::config() const {
  return impl_->config;
}
cv::Size LibcameraCamera::stillSize() const {
  return impl_->still;
}
cv::Size LibcameraCamera::previewSize() const {
  return impl_->preview;
}

void LibcameraCamera::lockSettings(const CaptureSettings& settings) {
  auto& d = *impl_;
  if (settings.exposureUs <= 0 || settings.analogueGain < 1.0 || settings.redGain <= 0.0 ||
      settings.blueGain <= 0.0) {
    d.fail(CameraErrorKind::kUnsupported,
           "invalid settings (exposureUs and colour gains must be > 0, analogueGain >= 1)");
  }
  d.settings = settings;
  d.settingsSet = true;
  if (d.cam) {
    d.computeUnsupported();
    // Controls go in with Camera::start (0.0.3 applies them from the first frame): restart.
    if (d.running) {
      const bool forPreview = d.runningPreview;
      d.stop();
      d.start(forPreview);
    }
  }
}

CaptureSettings LibcameraCamera::settings() const {
  return impl_->settings;
}
std::vector<std::string> LibcameraCamera::unsupportedSettings() const {
  return impl_->unsupported;
}

Frame LibcameraCamera::captureStill(const StillRequest& request) {
  auto& d = *impl_;
  d.requireOpen("captureStill");
  if (!d.configured) {
    configure(d.config);
  }
  const bool resume = d.previewWanted;
  if (d.running && d.runningPreview) {
    d.stop();
  }
  std::optional<Frame> frame;
  try {
    d.start(false);
    frame = d.grab(d.config.timeout, false);
    d.stop();
    if (resume) {
      d.start(true);
    }
  } catch (...) {
    d.stop();
    throw;
  }
  if (!frame) {
    d.fail(CameraErrorKind::kTimeout,
           "no frame within " + std::to_string(d.config.timeout.count()) + " ms");
  }
  frame->meta.shot = request.shot;
  return std::move(*frame);
}

void LibcameraCamera::startPreview() {
  auto& d = *impl_;
  d.requireOpen("startPreview");
  if (!d.configured) {
    configure(d.config);
  }
  d.previewWanted = true;
  if (d.running && !d.runningPreview) {
    d.stop();
  }
  d.start(true);
}

std::optional<Frame> LibcameraCamera::nextPreviewFrame(std::chrono::milliseconds timeout) {
  auto& d = *impl_;
  d.requireOpen("nextPreviewFrame");
  if (!d.previewWanted) {
    d.fail(CameraErrorKind::kState, "nextPreviewFrame: the preview is not running");
  }
  if (!d.running) {
    d.start(true);
  }
  return d.grab(timeout, true);
}

void LibcameraCamera::stopPreview() noexcept {
  impl_->previewWanted = false;
  impl_->stop();
}

bool LibcameraCamera::previewRunning() const {
  return impl_->previewWanted;
}

bool LibcameraCamera::reconnect() {
  auto& d = *impl_;
  const bool wantPreview = d.previewWanted || d.resumePreview;
  close();
  d.resumePreview = wantPreview;
  try {
    open();
  } catch (const CameraError& e) {
    if (e.kind() == CameraErrorKind::kNotFound) {
      return false;
    }
    throw;
  }
  if (d.configured) {
    configure(d.config);
  }
  if (wantPreview) {
    startPreview();
  }
  d.resumePreview = false;
  return true;
}

}  // namespace garmcap::capture
