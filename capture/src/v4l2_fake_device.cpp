#include "garmcap/capture/v4l2_fake_device.h"

#include <linux/videodev2.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/v4l2_decode.h"

namespace garmcap::capture {
namespace {

constexpr int kFakeFd = 73;
constexpr unsigned kOffsetShift = 26;  // buffer i is mapped at offset i << 26 (64 MiB apart)

cv::Mat defaultScene(std::uint64_t sequence, cv::Size size) {
  // A horizontal gradient with a bar that moves with the sequence number: frames differ, and
  // a decoded frame can be checked for orientation and colour order (red on the right).
  cv::Mat img(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y) {
    auto* row = img.ptr<cv::Vec3b>(y);
    for (int x = 0; x < size.width; ++x) {
      const auto r = static_cast<std::uint8_t>(255 * x / std::max(1, size.width - 1));
      const auto g = static_cast<std::uint8_t>(200 * y / std::max(1, size.height - 1));
      row[x] = cv::Vec3b(40, g, r);
    }
  }
  const int barX = static_cast<int>(sequence * 7 % static_cast<std::uint64_t>(size.width));
  cv::rectangle(img, cv::Rect(barX, 0, std::max(2, size.width / 40), size.height),
                cv::Scalar(255, 255, 255), cv::FILLED);
  return img;
}

}  // namespace

FakeV4l2Config defaultFakeUvcConfig(const std::string& path) {
  FakeV4l2Config c;
  c.path = path;
  const std::vector<cv::Size> sizes{{1920, 1080}, {1280, 720}, {640, 480}};
  c.formats = {{V4L2_PIX_FMT_MJPEG, sizes}, {V4L2_PIX_FMT_YUYV, sizes}};
  c.controls[V4L2_CID_EXPOSURE_AUTO] = {0, 3, 1, 3};  // aperture priority by default
  c.controls[V4L2_CID_EXPOSURE_ABSOLUTE] = {3, 2047, 1, 250};
  c.controls[V4L2_CID_EXPOSURE_AUTO_PRIORITY] = {0, 1, 1, 1};
  c.controls[V4L2_CID_GAIN] = {0, 255, 1, 64};
  c.controls[V4L2_CID_AUTO_WHITE_BALANCE] = {0, 1, 1, 1};
  c.controls[V4L2_CID_WHITE_BALANCE_TEMPERATURE] = {2000, 6500, 1, 4000};
  c.controls[V4L2_CID_FOCUS_AUTO] = {0, 1, 1, 1};
  c.controls[V4L2_CID_FOCUS_ABSOLUTE] = {0, 250, 5, 0};
  return c;
}

FakeV4l2Device::FakeV4l2Device(FakeV4l2Config config)
    : config_(std::move(config)), source_(defaultScene) {
  if (!config_.formats.empty() && !config_.formats.front().sizes.empty()) {
    fourcc_ = config_.formats.front().fourcc;
    size_ = config_.formats.front().sizes.front();
  }
}

FakeV4l2Device::~FakeV4l2Device() = default;

int FakeV4l2Device::fail(int err) {
  errno = err;
  return -1;
}

bool FakeV4l2Device::validFd(int fd) {
  return fd_ >= 0 && fd == fd_;
}

void FakeV4l2Device::setPresent(bool present) {
  present_ = present;
  if (!present && fd_ >= 0) {
    unplugged_ = true;
  }
}

void FakeV4l2Device::setBusy(bool busy) {
  busy_ = busy;
}
void FakeV4l2Device::setStalled(bool stalled) {
  stalled_ = stalled;
}

void FakeV4l2Device::injectFrameFaults(FakeFrameFault fault, int count) {
  fault_ = fault;
  faultCount_ = count;
}

void FakeV4l2Device::setFrameSource(FrameSource source) {
  source_ = std::move(source);
}

int FakeV4l2Device::completeFrames(int count) {
  int done = 0;
  for (int i = 0; i < count && streaming_; ++i) {
    const std::size_t before = done_.size();
    completeFrame();
    if (done_.size() == before) {
      break;  // no queued buffer left
    }
    ++done;
  }
  return done;
}

std::int32_t FakeV4l2Device::control(std::uint32_t id) const {
  if (auto it = values_.find(id); it != values_.end()) {
    return it->second;
  }
  auto c = config_.controls.find(id);
  return c == config_.controls.end() ? 0 : c->second.defaultValue;
}

std::size_t FakeV4l2Device::buffersMapped() const {
  return static_cast<std::size_t>(
      std::count_if(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped; }));
}

std::uint32_t FakeV4l2Device::bytesPerLine() const {
  return fourcc_ == V4L2_PIX_FMT_YUYV ? static_cast<std::uint32_t>(size_.width) * 2u : 0u;
}

std::uint32_t FakeV4l2Device::sizeImage() const {
  // MJPEG: a worst-case bound, as UVC drivers report it.
  return static_cast<std::uint32_t>(size_.width) * static_cast<std::uint32_t>(size_.height) * 2u;
}

int FakeV4l2Device::open(const std::string& path, int /*flags*/) {
  if (path != config_.path || !present_) {
    return fail(ENOENT);
  }
  if (busy_ || fd_ >= 0) {
    return fail(EBUSY);
  }
  fd_ = kFakeFd;
  ++openCount_;
  unplugged_ = false;
  return fd_;
}

int FakeV4l2Device::close(int fd) {
  if (!validFd(fd)) {
    return fail(EBADF);
  }
  // Closing releases everything the kernel holds for the file, mapped or not.
  streaming_ = false;
  buffers_.clear();
  done_.clear();
  fd_ = -1;
  unplugged_ = false;
  return 0;
}

std::vector<std::uint8_t> FakeV4l2Device::renderFrame() {
  cv::Mat bgr = source_(sequence_, size_);
  if (bgr.size() != size_ || bgr.type() != CV_8UC3) {
    cv::Mat resized;
    cv::resize(bgr, resized, size_);
    bgr = resized;
  }
  if (fourcc_ == V4L2_PIX_FMT_YUYV) {
    return encodeYuyv(bgr);
  }
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
  return jpeg;
}

void FakeV4l2Device::completeFrame() {
  auto it =
      std::find_if(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.queued; });
  if (it == buffers_.end()) {
    return;  // no buffer queued: the driver drops the frame
  }
  std::vector<std::uint8_t> data = renderFrame();
  FakeFrameFault fault = FakeFrameFault::kNone;
  if (faultCount_ > 0) {
    fault = fault_;
    --faultCount_;
  }
  it->error = false;
  switch (fault) {
    case FakeFrameFault::kNone:
      break;
    case FakeFrameFault::kTruncated:
      data.resize(data.size() / 2);
      break;
    case FakeFrameFault::kNoStart:
      data[0] = 0x00;
      break;
    case FakeFrameFault::kTiny:
      data.resize(std::min<std::size_t>(data.size(), 40));
      break;
    case FakeFrameFault::kErrorFlag:
      it->error = true;
      break;
  }
  const std::size_t n = std::min(data.size(), it->memory.size());
  std::memcpy(it->memory.data(), data.data(), n);
  it->bytesUsed = static_cast<std::uint32_t>(n);
  it->queued = false;
  it->sequence = static_cast<std::uint32_t>(sequence_);
  it->timestampUs = static_cast<std::int64_t>(sequence_) * 33333;  // 30 fps
  ++sequence_;
  done_.push_back(static_cast<std::size_t>(it - buffers_.begin()));
}

int FakeV4l2Device::poll(pollfd* fds, nfds_t count, int /*timeoutMs*/) {
  int ready = 0;
  for (nfds_t i = 0; i < count; ++i) {
    fds[i].revents = 0;
    if (!validFd(fds[i].fd)) {
      fds[i].revents = POLLNVAL;
      ++ready;
      continue;
    }
    if (unplugged_) {
      fds[i].revents = POLLERR;
      ++ready;
      continue;
    }
    if (!streaming_) {
      // V4L2 reports POLLERR when polling a queue that is not streaming.
      fds[i].revents = POLLERR;
      ++ready;
      continue;
    }
    if (!stalled_ && done_.empty()) {
      completeFrame();
    }
    if (!done_.empty()) {
      fds[i].revents = static_cast<short>(fds[i].events & (POLLIN | POLLRDNORM));
      if (fds[i].revents != 0) {
        ++ready;
      }
    }
  }
  // A stalled device makes the caller wait its full timeout; the fake returns at once, which
  // is what a test wants.
  return ready;
}

void* FakeV4l2Device::mmap(void* /*start*/, std::size_t length, int /*prot*/, int /*flags*/, int fd,
                           off_t offset) {
  if (!validFd(fd)) {
    errno = EBADF;
    return MAP_FAILED;
  }
  if (unplugged_) {
    errno = ENODEV;
    return MAP_FAILED;
  }
  const auto index = static_cast<std::size_t>(offset >> kOffsetShift);
  if ((offset & ((off_t{1} << kOffsetShift) - 1)) != 0 || index >= buffers_.size() ||
      length != buffers_[index].memory.size()) {
    errno = EINVAL;
    return MAP_FAILED;
  }
  buffers_[index].mapped = true;
  return buffers_[index].memory.data();
}

int FakeV4l2Device::munmap(void* start, std::size_t length) {
  for (auto& b : buffers_) {
    if (b.memory.data() == start) {
      if (!b.mapped || length != b.memory.size()) {
        return fail(EINVAL);
      }
      b.mapped = false;
      return 0;
    }
  }
  return fail(EINVAL);
}

int FakeV4l2Device::ioctl(int fd, unsigned long request, void* arg) {
  if (!validFd(fd)) {
    return fail(EBADF);
  }
  if (unplugged_) {
    return fail(ENODEV);
  }
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      std::memset(cap, 0, sizeof(*cap));
      std::snprintf(reinterpret_cast<char*>(cap->driver), sizeof(cap->driver), "uvcvideo");
      std::snprintf(reinterpret_cast<char*>(cap->card), sizeof(cap->card), "%s",
                    config_.card.c_str());
      cap->device_caps = config_.videoCapture ? (V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING)
                                              : (V4L2_CAP_VIDEO_OUTPUT | V4L2_CAP_STREAMING);
      cap->capabilities = cap->device_caps | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* f = static_cast<v4l2_fmtdesc*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || f->index >= config_.formats.size()) {
        return fail(EINVAL);
      }
      f->pixelformat = config_.formats[f->index].fourcc;
      f->flags = f->pixelformat == V4L2_PIX_FMT_MJPEG ? V4L2_FMT_FLAG_COMPRESSED : 0u;
      std::snprintf(reinterpret_cast<char*>(f->description), sizeof(f->description), "%s",
                    fourccToString(f->pixelformat).c_str());
      return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
      auto* s = static_cast<v4l2_frmsizeenum*>(arg);
      for (const auto& fmt : config_.formats) {
        if (fmt.fourcc == s->pixel_format) {
          if (s->index >= fmt.sizes.size()) {
            return fail(EINVAL);
          }
          s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
          s->discrete.width = static_cast<std::uint32_t>(fmt.sizes[s->index].width);
          s->discrete.height = static_cast<std::uint32_t>(fmt.sizes[s->index].height);
          return 0;
        }
      }
      return fail(EINVAL);
    }
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT:
    case VIDIOC_TRY_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return fail(EINVAL);
      }
      if (request != VIDIOC_G_FMT) {
        if (request == VIDIOC_S_FMT && (!buffers_.empty() || streaming_)) {
          return fail(EBUSY);
        }
        // Like drivers: never fail on an unknown format or size, adjust to the nearest.
        const FakeV4l2Format* chosen = &config_.formats.front();
        for (const auto& fmt : config_.formats) {
          if (fmt.fourcc == f->fmt.pix.pixelformat) {
            chosen = &fmt;
          }
        }
        cv::Size best = chosen->sizes.front();
        long bestCost = -1;
        for (const auto& s : chosen->sizes) {
          const long cost =
              std::labs(static_cast<long>(s.width) - static_cast<long>(f->fmt.pix.width)) +
              std::labs(static_cast<long>(s.height) - static_cast<long>(f->fmt.pix.height));
          if (bestCost < 0 || cost < bestCost) {
            bestCost = cost;
            best = s;
          }
        }
        if (request == VIDIOC_S_FMT) {
          fourcc_ = chosen->fourcc;
          size_ = best;
        } else {
          f->fmt.pix.pixelformat = chosen->fourcc;
          f->fmt.pix.width = static_cast<std::uint32_t>(best.width);
          f->fmt.pix.height = static_cast<std::uint32_t>(best.height);
          return 0;
        }
      }
      f->fmt.pix.pixelformat = fourcc_;
      f->fmt.pix.width = static_cast<std::uint32_t>(size_.width);
      f->fmt.pix.height = static_cast<std::uint32_t>(size_.height);
      f->fmt.pix.field = V4L2_FIELD_NONE;
      f->fmt.pix.bytesperline = bytesPerLine();
      f->fmt.pix.sizeimage = fourcc_ == V4L2_PIX_FMT_YUYV
                                 ? bytesPerLine() * static_cast<std::uint32_t>(size_.height)
                                 : sizeImage();
      return 0;
    }
    case VIDIOC_S_PARM:
    case VIDIOC_G_PARM: {
      auto* p = static_cast<v4l2_streamparm*>(arg);
      if (p->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return fail(EINVAL);
      }
      p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      p->parm.capture.timeperframe = {1, 30};
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || r->memory != V4L2_MEMORY_MMAP) {
        return fail(EINVAL);
      }
      if (streaming_ || buffersMapped() > 0) {
        return fail(EBUSY);
      }
      buffers_.clear();
      done_.clear();
      const std::uint32_t n = std::min(r->count, config_.maxBuffers);
      const std::uint32_t length = fourcc_ == V4L2_PIX_FMT_YUYV
                                       ? bytesPerLine() * static_cast<std::uint32_t>(size_.height)
                                       : sizeImage();
      for (std::uint32_t i = 0; i < n; ++i) {
        Buffer b;
        b.memory.assign(length, 0);
        buffers_.push_back(std::move(b));
      }
      r->count = n;
      return 0;
    }
    case VIDIOC_QUERYBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->index >= buffers_.size()) {
        return fail(EINVAL);
      }
      b->length = static_cast<std::uint32_t>(buffers_[b->index].memory.size());
      b->m.offset = b->index << kOffsetShift;
      b->memory = V4L2_MEMORY_MMAP;
      b->flags = buffers_[b->index].queued ? V4L2_BUF_FLAG_QUEUED : 0u;
      return 0;
    }
    case VIDIOC_QBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP ||
          b->index >= buffers_.size()) {
        return fail(EINVAL);
      }
      auto& buf = buffers_[b->index];
      const bool waiting = std::find(done_.begin(), done_.end(), b->index) != done_.end();
      if (buf.queued || waiting) {
        return fail(EINVAL);  // already owned by the driver
      }
      buf.queued = true;
      return 0;
    }
    case VIDIOC_DQBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP) {
        return fail(EINVAL);
      }
      if (!streaming_) {
        return fail(EINVAL);
      }
      if (done_.empty()) {
        return fail(EAGAIN);
      }
      const std::size_t i = done_.front();
      done_.erase(done_.begin());
      const auto& buf = buffers_[i];
      b->index = static_cast<std::uint32_t>(i);
      b->bytesused = buf.bytesUsed;
      b->length = static_cast<std::uint32_t>(buf.memory.size());
      b->sequence = buf.sequence;
      b->flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | (buf.error ? V4L2_BUF_FLAG_ERROR : 0u);
      b->timestamp.tv_sec = buf.timestampUs / 1000000;
      b->timestamp.tv_usec = buf.timestampUs % 1000000;
      return 0;
    }
    case VIDIOC_STREAMON: {
      if (*static_cast<int*>(arg) != V4L2_BUF_TYPE_VIDEO_CAPTURE || buffers_.empty()) {
        return fail(EINVAL);
      }
      streaming_ = true;
      return 0;
    }
    case VIDIOC_STREAMOFF: {
      if (*static_cast<int*>(arg) != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return fail(EINVAL);
      }
      // STREAMOFF returns every buffer to user space (dequeued, not queued).
      streaming_ = false;
      done_.clear();
      for (auto& b : buffers_) {
        b.queued = false;
      }
      return 0;
    }
    case VIDIOC_QUERYCTRL: {
      auto* q = static_cast<v4l2_queryctrl*>(arg);
      auto it = config_.controls.find(q->id);
      if (it == config_.controls.end()) {
        return fail(EINVAL);
      }
      q->minimum = it->second.minimum;
      q->maximum = it->second.maximum;
      q->step = it->second.step;
      q->default_value = it->second.defaultValue;
      q->flags = 0;
      q->type = q->id == V4L2_CID_EXPOSURE_AUTO ? V4L2_CTRL_TYPE_MENU : V4L2_CTRL_TYPE_INTEGER;
      return 0;
    }
    case VIDIOC_G_CTRL: {
      auto* c = static_cast<v4l2_control*>(arg);
      if (!config_.controls.count(c->id)) {
        return fail(EINVAL);
      }
      c->value = control(c->id);
      return 0;
    }
    case VIDIOC_S_CTRL: {
      auto* c = static_cast<v4l2_control*>(arg);
      auto it = config_.controls.find(c->id);
      if (it == config_.controls.end()) {
        return fail(EINVAL);
      }
      if (c->value < it->second.minimum || c->value > it->second.maximum) {
        return fail(ERANGE);
      }
      // UVC: the absolute exposure/temperature/focus are read-only while their auto control
      // is on; writing them then fails with EACCES (the reason to switch auto off first).
      if ((c->id == V4L2_CID_EXPOSURE_ABSOLUTE &&
           control(V4L2_CID_EXPOSURE_AUTO) != V4L2_EXPOSURE_MANUAL) ||
          (c->id == V4L2_CID_WHITE_BALANCE_TEMPERATURE &&
           control(V4L2_CID_AUTO_WHITE_BALANCE) != 0) ||
          (c->id == V4L2_CID_FOCUS_ABSOLUTE && control(V4L2_CID_FOCUS_AUTO) != 0)) {
        return fail(EACCES);
      }
      values_[c->id] = c->value;
      controlWrites_.push_back(c->id);
      return 0;
    }
    default:
      return fail(ENOTTY);
  }
}

}  // namespace garmcap::capture
