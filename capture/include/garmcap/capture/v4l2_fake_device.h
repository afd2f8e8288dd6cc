#pragma once
// A deterministic, in-memory V4L2 capture device behind the V4l2Device seam (Chromium's
// FakeV4L2Impl is the model). It implements the subset of the V4L2 API a UVC webcam offers —
// QUERYCAP, ENUM_FMT, ENUM_FRAMESIZES, G/S_FMT, S_PARM, REQBUFS, QUERYBUF, QBUF, DQBUF,
// STREAMON/OFF, QUERYCTRL, G/S_CTRL, mmap, poll — and enforces the kernel's bookkeeping rules
// (no S_FMT or REQBUFS while buffers are mapped or streaming, no double QBUF, DQBUF only while
// streaming) so that bugs in V4l2Camera fail tests instead of cameras.
//
// Frames: each poll() while streaming with a queued buffer "completes" one frame, rendered by
// the frame source at the negotiated size and encoded as MJPEG or YUYV. Faults can be injected:
// unplug (ENODEV from then on, POLLERR), busy (EBUSY at open), stalled stream (poll times out),
// broken MJPEG frames and V4L2_BUF_FLAG_ERROR buffers.
//
// Not thread-safe: used from the camera's thread, like the device.

#include <cstdint>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/capture/v4l2_device.h"

namespace garmcap::capture {

struct FakeV4l2Control {
  std::int32_t minimum = 0;
  std::int32_t maximum = 1;
  std::int32_t step = 1;
  std::int32_t defaultValue = 0;
};

struct FakeV4l2Format {
  std::uint32_t fourcc = 0;     ///< V4L2_PIX_FMT_MJPEG or V4L2_PIX_FMT_YUYV
  std::vector<cv::Size> sizes;  ///< discrete frame sizes
};

struct FakeV4l2Config {
  std::string path = "/dev/video0";
  std::string card = "Fake UVC Camera";
  bool videoCapture = true;  ///< false: QUERYCAP reports an output-only device
  std::vector<FakeV4l2Format> formats;
  std::map<std::uint32_t, FakeV4l2Control> controls;
  std::uint32_t maxBuffers = 4;  ///< REQBUFS clamps the count to this
};

/// A webcam with MJPEG and YUYV at 1920x1080, 1280x720 and 640x480 and the usual UVC controls
/// (exposure auto/absolute/auto-priority, gain, auto white balance, white balance temperature,
/// focus auto/absolute).
FakeV4l2Config defaultFakeUvcConfig(const std::string& path = "/dev/video0");

enum class FakeFrameFault {
  kNone,
  kTruncated,  ///< MJPEG cut in the middle (no FFD9 end marker)
  kNoStart,    ///< MJPEG without its FFD8 start marker
  kTiny,       ///< a few bytes only
  kErrorFlag,  ///< V4L2_BUF_FLAG_ERROR set on the buffer
};

class FakeV4l2Device final : public V4l2Device {
 public:
  /// Renders the scene for frame `sequence` at `size` as BGR.
  using FrameSource = std::function<cv::Mat(std::uint64_t sequence, cv::Size size)>;

  explicit FakeV4l2Device(FakeV4l2Config config);
  ~FakeV4l2Device() override;

  // --- V4l2Device ---
  int open(const std::string& path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(void* start, std::size_t length, int prot, int flags, int fd, off_t offset) override;
  int munmap(void* start, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeoutMs) override;

  // --- fault injection ---
  /// false = unplugged: open() fails with ENOENT, calls on an open fd fail with ENODEV.
  void setPresent(bool present);
  void setBusy(bool busy);
  /// Stalled: poll() reports nothing (a timeout) while true.
  void setStalled(bool stalled);
  /// The next `count` frames carry `fault`.
  void injectFrameFaults(FakeFrameFault fault, int count);
  void setFrameSource(FrameSource source);
  /// Completes up to `count` frames now (as if the application fell behind); returns how many
  /// completed (limited by the buffers queued).
  int completeFrames(int count);

  // --- inspection ---
  /// Current control value (the default when never set).
  std::int32_t control(std::uint32_t id) const;
  /// Control ids in the order S_CTRL set them.
  const std::vector<std::uint32_t>& controlWrites() const { return controlWrites_; }
  int openCount() const { return openCount_; }
  bool isOpen() const { return fd_ >= 0; }
  bool streaming() const { return streaming_; }
  std::uint32_t fourcc() const { return fourcc_; }
  cv::Size size() const { return size_; }
  std::size_t buffersAllocated() const { return buffers_.size(); }
  std::size_t buffersMapped() const;
  std::uint64_t framesDelivered() const { return sequence_; }
  /// Frames completed by the device but not yet dequeued.
  std::size_t framesPending() const { return done_.size(); }

 private:
  struct Buffer {
    std::vector<std::uint8_t> memory;
    std::uint32_t bytesUsed = 0;
    bool queued = false;
    bool mapped = false;
    bool error = false;
    std::uint32_t sequence = 0;
    std::int64_t timestampUs = 0;
  };

  int fail(int err);
  bool validFd(int fd);
  void completeFrame();
  std::vector<std::uint8_t> renderFrame();
  std::uint32_t sizeImage() const;
  std::uint32_t bytesPerLine() const;

  FakeV4l2Config config_;
  FrameSource source_;
  bool present_ = true;
  bool busy_ = false;
  bool stalled_ = false;
  bool unplugged_ = false;  // unplugged while open: ENODEV until closed
  FakeFrameFault fault_ = FakeFrameFault::kNone;
  int faultCount_ = 0;
  int fd_ = -1;
  int openCount_ = 0;
  std::uint32_t fourcc_ = 0;
  cv::Size size_;
  std::vector<Buffer> buffers_;
  std::vector<std::size_t> done_;  // completed, waiting for DQBUF, in order
  bool streaming_ = false;
  std::uint64_t sequence_ = 0;
  std::map<std::uint32_t, std::int32_t> values_;
  std::vector<std::uint32_t> controlWrites_;
};

}  // namespace garmcap::capture
