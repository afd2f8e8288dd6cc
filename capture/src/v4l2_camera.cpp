#include "garmcap/capture/v4l2_camera.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <span>

#include "garmcap/capture/v4l2_decode.h"

namespace garmcap::capture {
namespace {

bool decodable(std::uint32_t fourcc) {
  return fourcc == V4L2_PIX_FMT_MJPEG || fourcc == V4L2_PIX_FMT_YUYV;
}

std::uint32_t fourccFor(PixelFormat f) {
  switch (f) {
    case PixelFormat::kMjpeg:
      return V4L2_PIX_FMT_MJPEG;
    case PixelFormat::kYuyv:
      return V4L2_PIX_FMT_YUYV;
    default:
      return 0;
  }
}

long area(cv::Size s) {
  return static_cast<long>(s.width) * static_cast<long>(s.height);
}

std::string describe(const std::vector<V4l2FormatOption>& offered) {
  std::string s;
  for (const auto& f : offered) {
    if (!s.empty()) {
      s += ", ";
    }
    s += fourccToString(f.fourcc);
    if (!f.sizes.empty()) {
      s += " up to " + std::to_string(f.sizes.front().width) + "x" +
           std::to_string(f.sizes.front().height);
    }
  }
  return s.empty() ? "none" : s;
}

bool sameFormat(const V4l2FormatChoice& a, const V4l2FormatChoice& b) {
  return a.fourcc == b.fourcc && a.size == b.size;
}

}  // namespace

std::optional<V4l2FormatChoice> chooseV4l2Format(const std::vector<V4l2FormatOption>& offered,
                                                 PixelFormat want, cv::Size wanted) {
  const V4l2FormatOption* format = nullptr;
  const std::uint32_t wantedFourcc = fourccFor(want);
  if (want == PixelFormat::kBgr888) {
    return std::nullopt;  // UVC cameras do not deliver packed RGB
  }
  for (std::uint32_t preferred : {V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_YUYV}) {
    if (wantedFourcc != 0 && preferred != wantedFourcc) {
      continue;
    }
    for (const auto& f : offered) {
      if (f.fourcc == preferred && !f.sizes.empty()) {
        format = &f;
        break;
      }
    }
    if (format != nullptr) {
      break;
    }
  }
  if (format == nullptr) {
    return std::nullopt;
  }
  const auto largest = *std::max_element(format->sizes.begin(), format->sizes.end(),
                                         [](cv::Size a, cv::Size b) { return area(a) < area(b); });
  if (wanted.width <= 0 || wanted.height <= 0) {
    return V4l2FormatChoice{format->fourcc, largest};
  }
  std::optional<cv::Size> best;
  for (const auto& s : format->sizes) {
    if (s == wanted) {
      return V4l2FormatChoice{format->fourcc, s};
    }
    if (s.width >= wanted.width && s.height >= wanted.height && (!best || area(s) < area(*best))) {
      best = s;
    }
  }
  return V4l2FormatChoice{format->fourcc, best.value_or(largest)};
}

V4l2Camera::V4l2Camera(std::string path, std::unique_ptr<V4l2Device> device)
    : path_(std::move(path)), dev_(std::move(device)) {}

V4l2Camera::~V4l2Camera() {
  close();
}

int V4l2Camera::xioctl(unsigned long request, void* arg) {
  int r = 0;
  for (int attempt = 0; attempt < 4; ++attempt) {
    r = dev_->ioctl(fd_, request, arg);
    if (r != -1 || errno != EINTR) {
      break;
    }
  }
  return r;
}

void V4l2Camera::failErrno(const std::string& what, int err) {
  const std::string reason = std::strerror(err);
  if (err == ENODEV || err == ENXIO) {
    throw CameraError(CameraErrorKind::kDisconnected,
                      "camera at " + path_ + " disconnected (" + what + ": " + reason + ")");
  }
  throw CameraError(CameraErrorKind::kIo, "camera at " + path_ + ": " + what + ": " + reason);
}

void V4l2Camera::requireOpen(const char* what) const {
  if (fd_ < 0) {
    throw CameraError(CameraErrorKind::kState,
                      std::string(what) + ": camera at " + path_ + " is not open");
  }
}

void V4l2Camera::open() {
  if (fd_ >= 0) {
    return;
  }
  const int fd = dev_->open(path_, O_RDWR | O_NONBLOCK);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENXIO || err == ENODEV) {
      throw CameraError(CameraErrorKind::kNotFound, "no camera at " + path_);
    }
    if (err == EBUSY) {
      throw CameraError(CameraErrorKind::kBusy,
                        "camera at " + path_ + " is busy (another program has it open)");
    }
    if (err == EACCES || err == EPERM) {
      throw CameraError(CameraErrorKind::kIo,
                        "no permission to open " + path_ + " (is the user in group 'video'?)");
    }
    throw CameraError(CameraErrorKind::kIo, "cannot open " + path_ + ": " + std::strerror(err));
  }
  fd_ = fd;
  v4l2_capability cap{};
  if (xioctl(VIDIOC_QUERYCAP, &cap) < 0) {
    const int err = errno;
    close();
    if (err == ENOTTY || err == EINVAL) {
      throw CameraError(CameraErrorKind::kUnsupported, path_ + " is not a V4L2 device");
    }
    failErrno("VIDIOC_QUERYCAP", err);
  }
  card_ = reinterpret_cast<const char*>(cap.card);
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    close();
    throw CameraError(CameraErrorKind::kUnsupported,
                      path_ + " (" + card_ +
                          ") is not a streaming video capture device (UVC cameras also "
                          "create a metadata node; try the other /dev/video* of the camera)");
  }
  if (settingsApplied_) {
    applySettings();
  }
}

void V4l2Camera::close() noexcept {
  stopStream();
  previewWanted_ = false;
  resumePreview_ = false;
  if (fd_ >= 0) {
    dev_->close(fd_);
    fd_ = -1;
  }
}

std::vector<V4l2FormatOption> V4l2Camera::enumerateFormats() {
  std::vector<V4l2FormatOption> out;
  for (std::uint32_t i = 0;; ++i) {
    v4l2_fmtdesc desc{};
    desc.index = i;
    desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(VIDIOC_ENUM_FMT, &desc) < 0) {
      if (errno == EINVAL) {
        break;  // end of the list
      }
      failErrno("VIDIOC_ENUM_FMT", errno);
    }
    V4l2FormatOption option{desc.pixelformat, {}};
    for (std::uint32_t j = 0;; ++j) {
      v4l2_frmsizeenum size{};
      size.index = j;
      size.pixel_format = desc.pixelformat;
      if (xioctl(VIDIOC_ENUM_FRAMESIZES, &size) < 0) {
        if (errno == EINVAL || errno == ENOTTY) {
          break;
        }
        failErrno("VIDIOC_ENUM_FRAMESIZES", errno);
      }
      if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
        option.sizes.emplace_back(static_cast<int>(size.discrete.width),
                                  static_cast<int>(size.discrete.height));
      } else {
        // Stepwise/continuous: the extremes are real sizes; anything between is allowed, and
        // S_FMT adjusts a request to the step, so offering the extremes plus the preview's
        // 640x480 (when inside) is enough for negotiation.
        const auto& sw = size.stepwise;
        option.sizes.emplace_back(static_cast<int>(sw.max_width), static_cast<int>(sw.max_height));
        option.sizes.emplace_back(static_cast<int>(sw.min_width), static_cast<int>(sw.min_height));
        if (sw.min_width <= 640 && sw.max_width >= 640 && sw.min_height <= 480 &&
            sw.max_height >= 480) {
          option.sizes.emplace_back(640, 480);
        }
        break;
      }
    }
    out.push_back(std::move(option));
  }
  return out;
}

void V4l2Camera::configure(const CameraConfig& config) {
  requireOpen("configure");
  if (config.stillWidth < 0 || config.stillHeight < 0 || config.previewWidth < 0 ||
      config.previewHeight < 0 || config.timeout.count() <= 0 || config.settleFrames < 0) {
    throw CameraError(
        CameraErrorKind::kUnsupported,
        "camera at " + path_ + ": invalid configuration (negative size, settle frames or timeout)");
  }
  const bool resume = previewWanted_;
  stopStream();
  offered_ = enumerateFormats();
  const cv::Size previewWanted = (config.previewWidth > 0 && config.previewHeight > 0)
                                     ? cv::Size(config.previewWidth, config.previewHeight)
                                     : cv::Size(640, 480);
  const auto still =
      chooseV4l2Format(offered_, config.pixelFormat, {config.stillWidth, config.stillHeight});
  const auto preview = chooseV4l2Format(offered_, config.pixelFormat, previewWanted);
  if (!still || !preview) {
    throw CameraError(CameraErrorKind::kUnsupported,
                      "camera at " + path_ + " offers no usable format for " +
                          toString(config.pixelFormat) + " (offered: " + describe(offered_) +
                          "; decodable: MJPG, YUYV)");
  }
  config_ = config;
  still_ = *still;
  preview_ = *preview;
  configured_ = true;
  if (resume) {
    startPreview();
  }
}

std::int32_t V4l2Camera::setControl(std::uint32_t id, std::int32_t value, const char* setting) {
  v4l2_queryctrl query{};
  query.id = id;
  if (xioctl(VIDIOC_QUERYCTRL, &query) < 0) {
    if (errno == ENODEV) {
      failErrno("VIDIOC_QUERYCTRL", errno);
    }
    if (setting != nullptr) {
      unsupported_.emplace_back(setting);
    }
    return value;
  }
  if ((query.flags & (V4L2_CTRL_FLAG_DISABLED | V4L2_CTRL_FLAG_READ_ONLY)) != 0) {
    if (setting != nullptr) {
      unsupported_.emplace_back(setting);
    }
    return value;
  }
  std::int32_t v = std::clamp(value, query.minimum, query.maximum);
  if (query.step > 1) {
    v = query.minimum + (v - query.minimum) / query.step * query.step;
  }
  v4l2_control control{};
  control.id = id;
  control.value = v;
  if (xioctl(VIDIOC_S_CTRL, &control) < 0) {
    if (errno == ENODEV) {
      failErrno("VIDIOC_S_CTRL", errno);
    }
    if (setting != nullptr) {
      unsupported_.emplace_back(setting);
    }
  }
  return v;
}

void V4l2Camera::applySettings() {
  unsupported_.clear();
  const auto& s = settings_;
  // UVC: the absolute value is writable only once its auto control is off, so auto first.
  if (!s.autoExposure) {
    setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "autoExposure");
    setControl(V4L2_CID_EXPOSURE_AUTO_PRIORITY, 0, nullptr);  // keep the frame rate fixed
    const auto units = static_cast<std::int32_t>(std::lround(s.exposureUs / 100.0));
    setControl(V4L2_CID_EXPOSURE_ABSOLUTE, std::max(1, units), "exposureUs");
    // V4L2_CID_GAIN is in device units; scale its default by the requested analogue gain.
    v4l2_queryctrl gain{};
    gain.id = V4L2_CID_GAIN;
    if (xioctl(VIDIOC_QUERYCTRL, &gain) == 0) {
      setControl(V4L2_CID_GAIN,
                 static_cast<std::int32_t>(std::lround(gain.default_value * s.analogueGain)),
                 "analogueGain");
    } else {
      unsupported_.emplace_back("analogueGain");
    }
  } else {
    // Aperture priority is what UVC cameras call "auto"; fully-auto (0) is rarely offered.
    const std::size_t before = unsupported_.size();
    setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_APERTURE_PRIORITY, "autoExposure");
    if (unsupported_.size() != before) {
      unsupported_.resize(before);
      setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_AUTO, "autoExposure");
    }
  }
  if (!s.autoWhiteBalance) {
    setControl(V4L2_CID_AUTO_WHITE_BALANCE, 0, "autoWhiteBalance");
    setControl(V4L2_CID_WHITE_BALANCE_TEMPERATURE, s.whiteBalanceKelvin, "whiteBalanceKelvin");
  } else {
    setControl(V4L2_CID_AUTO_WHITE_BALANCE, 1, "autoWhiteBalance");
  }
  if (!s.autoFocus) {
    setControl(V4L2_CID_FOCUS_AUTO, 0, "autoFocus");
    setControl(V4L2_CID_FOCUS_ABSOLUTE, s.focusPosition, "focusPosition");
  } else {
    setControl(V4L2_CID_FOCUS_AUTO, 1, "autoFocus");
  }
  settingsApplied_ = true;
  settleLeft_ = config_.settleFrames;  // the sensor applies new controls a few frames late
}

void V4l2Camera::lockSettings(const CaptureSettings& settings) {
  if (settings.exposureUs <= 0 || settings.analogueGain < 1.0 || settings.whiteBalanceKelvin <= 0) {
    throw CameraError(CameraErrorKind::kUnsupported,
                      "camera at " + path_ +
                          ": invalid settings (exposureUs and whiteBalanceKelvin must be > 0, "
                          "analogueGain >= 1)");
  }
  settings_ = settings;
  settingsApplied_ = true;  // applied now if open, else at open()
  if (fd_ >= 0) {
    applySettings();
  }
}

void V4l2Camera::startStream(const V4l2FormatChoice& choice) {
  if (streaming_) {
    return;
  }
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(choice.size.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(choice.size.height);
  fmt.fmt.pix.pixelformat = choice.fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(VIDIOC_S_FMT, &fmt) < 0) {
    failErrno("VIDIOC_S_FMT " + fourccToString(choice.fourcc), errno);
  }
  // Drivers adjust rather than fail: always use what came back.
  streamFormat_ = {fmt.fmt.pix.pixelformat,
                   {static_cast<int>(fmt.fmt.pix.width), static_cast<int>(fmt.fmt.pix.height)}};
  if (!decodable(streamFormat_.fourcc)) {
    throw CameraError(CameraErrorKind::kUnsupported, "camera at " + path_ + " switched to " +
                                                         fourccToString(streamFormat_.fourcc) +
                                                         ", which is not decodable");
  }
  bytesPerLine_ = fmt.fmt.pix.bytesperline;
  if (streamFormat_.fourcc == V4L2_PIX_FMT_YUYV && bytesPerLine_ == 0) {
    bytesPerLine_ = static_cast<std::uint32_t>(streamFormat_.size.width) * 2u;
  }
  // Keep the reported sizes honest when the driver adjusted the request.
  if (sameFormat(choice, still_)) {
    still_ = streamFormat_;
  }
  if (sameFormat(choice, preview_)) {
    preview_ = streamFormat_;
  }

  v4l2_requestbuffers req{};
  req.count = kBufferCount;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_REQBUFS, &req) < 0) {
    failErrno("VIDIOC_REQBUFS", errno);
  }
  if (req.count < 2) {
    stopStream();
    throw CameraError(CameraErrorKind::kIo, "camera at " + path_ + ": driver granted " +
                                                std::to_string(req.count) +
                                                " buffer(s), at least 2 are needed");
  }
  buffers_.assign(req.count, Mapping{});
  try {
    for (std::uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(VIDIOC_QUERYBUF, &buf) < 0) {
        failErrno("VIDIOC_QUERYBUF", errno);
      }
      void* p = dev_->mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_,
                           static_cast<off_t>(buf.m.offset));
      if (p == MAP_FAILED) {
        failErrno("mmap of buffer " + std::to_string(i), errno);
      }
      buffers_[i] = {p, buf.length};
    }
    for (std::uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(VIDIOC_QBUF, &buf) < 0) {
        failErrno("VIDIOC_QBUF", errno);
      }
    }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(VIDIOC_STREAMON, &type) < 0) {
      failErrno("VIDIOC_STREAMON", errno);
    }
  } catch (...) {
    stopStream();
    throw;
  }
  streaming_ = true;
  settleLeft_ = config_.settleFrames;
}

void V4l2Camera::stopStream() noexcept {
  if (fd_ < 0) {
    buffers_.clear();
    streaming_ = false;
    return;
  }
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(VIDIOC_STREAMOFF, &type);  // fails only when unplugged; the close cleans up then
    streaming_ = false;
  }
  const bool hadBuffers = !buffers_.empty();
  for (auto& m : buffers_) {
    if (m.data != nullptr) {
      dev_->munmap(m.data, m.length);
    }
  }
  buffers_.clear();
  if (hadBuffers) {
    v4l2_requestbuffers req{};
    req.count = 0;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(VIDIOC_REQBUFS, &req);  // frees the driver's buffers so S_FMT may change size
  }
}

std::optional<Frame> V4l2Camera::grab(std::chrono::milliseconds timeout, bool preview) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  auto requeue = [this](std::uint32_t index) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = index;
    if (xioctl(VIDIOC_QBUF, &buf) < 0) {
      failErrno("VIDIOC_QBUF", errno);
    }
  };
  auto drop = [this](const std::string& reason) {
    ++stats_.framesDropped;
    stats_.lastDropReason = reason;
  };
  for (;;) {
    const auto left = deadline - Clock::now();
    if (left <= Clock::duration::zero()) {
      ++stats_.timeouts;
      return std::nullopt;
    }
    const auto remaining = std::chrono::ceil<std::chrono::milliseconds>(left);
    pollfd p{fd_, POLLIN, 0};
    const int r = dev_->poll(&p, 1, static_cast<int>(remaining.count()));
    if (r < 0) {
      if (errno == EINTR) {
        continue;
      }
      failErrno("poll", errno);
    }
    if (r == 0) {
      continue;
    }
    if ((p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
      stopStream();
      throw CameraError(CameraErrorKind::kDisconnected,
                        "camera at " + path_ + " disconnected (poll reported an error)");
    }
    // Drain: keep only the newest buffer, requeue the older ones (lowest latency).
    std::optional<v4l2_buffer> newest;
    for (;;) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      if (xioctl(VIDIOC_DQBUF, &buf) < 0) {
        if (errno == EAGAIN) {
          break;
        }
        const int err = errno;
        stopStream();
        failErrno("VIDIOC_DQBUF", err);
      }
      if (buf.index >= buffers_.size()) {
        throw CameraError(
            CameraErrorKind::kIo,
            "camera at " + path_ + ": driver returned unknown buffer " + std::to_string(buf.index));
      }
      if (newest) {
        requeue(newest->index);
      }
      newest = buf;
    }
    if (!newest) {
      continue;
    }
    const v4l2_buffer buf = *newest;
    if (settleLeft_ > 0) {
      --settleLeft_;
      requeue(buf.index);
      continue;
    }
    const auto& mapping = buffers_[buf.index];
    const std::span<const std::uint8_t> bytes(static_cast<const std::uint8_t*>(mapping.data),
                                              std::min<std::size_t>(buf.bytesused, mapping.length));
    cv::Mat bgr;
    std::string jpeg;
    if ((buf.flags & V4L2_BUF_FLAG_ERROR) != 0) {
      drop("buffer flagged V4L2_BUF_FLAG_ERROR");
    } else if (streamFormat_.fourcc == V4L2_PIX_FMT_MJPEG) {
      const MjpegCheck check = checkMjpegFrame(bytes);
      if (check != MjpegCheck::kOk) {
        drop(std::string("broken MJPEG frame: ") + toString(check));
      } else {
        bgr = decodeMjpeg(bytes);
        if (bgr.empty()) {
          drop("MJPEG frame could not be decoded");
        } else if (!preview) {
          // A still keeps the camera's own JPEG (Frame::encoded): decodeMjpeg is cv::imdecode
          // of exactly these bytes, so they are the frame, and the station stores them as they
          // are instead of encoding the decoded frame again.
          jpeg.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        }
      }
    } else {
      bgr = decodeYuyv(bytes, streamFormat_.size.width, streamFormat_.size.height,
                       static_cast<int>(bytesPerLine_));
      if (bgr.empty()) {
        drop("short YUYV frame (" + std::to_string(buf.bytesused) + " bytes)");
      }
    }
    // The pixels are copied out (decoded), so the buffer goes straight back to the driver.
    requeue(buf.index);
    if (bgr.empty()) {
      continue;
    }
    ++stats_.framesDecoded;
    Frame frame;
    frame.bgr = std::move(bgr);
    if (!jpeg.empty()) {
      frame.encoded = std::move(jpeg);
      frame.encodedMediaType = "image/jpeg";
    }
    auto& m = frame.meta;
    m.sequence = sequence_++;
    m.timestamp = std::chrono::seconds(buf.timestamp.tv_sec) +
                  std::chrono::microseconds(buf.timestamp.tv_usec);
    m.preview = preview;
    m.backend = "v4l2";
    m.device = path_;
    m.pixelFormat = fourccToString(streamFormat_.fourcc);
    if (settingsApplied_ && !settings_.autoExposure) {
      m.exposureUs = settings_.exposureUs;
      m.analogueGain = settings_.analogueGain;
    }
    if (settingsApplied_ && !settings_.autoWhiteBalance) {
      m.whiteBalanceKelvin = settings_.whiteBalanceKelvin;
    }
    return frame;
  }
}

Frame V4l2Camera::captureStill(const StillRequest& request) {
  requireOpen("captureStill");
  if (!configured_) {
    configure(config_);
  }
  const bool resume = previewWanted_;
  auto restorePreview = [&] {
    if (resume && !(streaming_ && sameFormat(streamFormat_, preview_))) {
      stopStream();
      startStream(preview_);
    } else if (!resume) {
      stopStream();
    }
  };
  std::optional<Frame> frame;
  try {
    if (streaming_ && !sameFormat(streamFormat_, still_)) {
      stopStream();
    }
    startStream(still_);
    frame = grab(config_.timeout, false);
    if (!frame) {
      std::string detail;
      if (!stats_.lastDropReason.empty()) {
        detail = " (" + std::to_string(stats_.framesDropped) +
                 " broken frame(s) dropped so far, last: " + stats_.lastDropReason + ")";
      }
      throw CameraError(CameraErrorKind::kTimeout, "no frame from camera at " + path_ + " within " +
                                                       std::to_string(config_.timeout.count()) +
                                                       " ms" + detail);
    }
    restorePreview();
  } catch (const CameraError& e) {
    if (e.kind() != CameraErrorKind::kDisconnected) {
      try {
        restorePreview();
      } catch (const CameraError&) {
        // The original error is the one to report; the preview is retried by the caller.
      }
    }
    throw;
  }
  frame->meta.shot = request.shot;
  return std::move(*frame);
}

void V4l2Camera::startPreview() {
  requireOpen("startPreview");
  if (!configured_) {
    configure(config_);
  }
  previewWanted_ = true;
  if (streaming_ && !sameFormat(streamFormat_, preview_)) {
    stopStream();
  }
  startStream(preview_);
}

std::optional<Frame> V4l2Camera::nextPreviewFrame(std::chrono::milliseconds timeout) {
  requireOpen("nextPreviewFrame");
  if (!previewWanted_) {
    throw CameraError(CameraErrorKind::kState,
                      "nextPreviewFrame: preview of camera at " + path_ + " is not running");
  }
  if (!streaming_) {
    startStream(preview_);
  }
  return grab(timeout, true);
}

void V4l2Camera::stopPreview() noexcept {
  previewWanted_ = false;
  stopStream();
}

bool V4l2Camera::reconnect() {
  // Remembered across failed attempts: the preview comes back with the device.
  const bool wantPreview = previewWanted_ || resumePreview_;
  close();
  resumePreview_ = wantPreview;
  try {
    open();
  } catch (const CameraError& e) {
    if (e.kind() == CameraErrorKind::kNotFound || e.kind() == CameraErrorKind::kDisconnected) {
      return false;
    }
    throw;
  }
  try {
    if (configured_) {
      configure(config_);
    }
    if (wantPreview) {
      startPreview();
    }
  } catch (const CameraError& e) {
    if (e.kind() == CameraErrorKind::kDisconnected) {
      close();
      resumePreview_ = wantPreview;
      return false;  // unplugged again while we set it up
    }
    throw;
  }
  resumePreview_ = false;
  return true;
}

}  // namespace garmcap::capture
