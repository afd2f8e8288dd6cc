#pragma once
// The syscall seam under the V4L2 back end: everything V4l2Camera does to a device goes through
// this interface, so its device-independent logic (format negotiation, buffer bookkeeping,
// broken-frame dropping, reconnection) runs in unit tests against FakeV4l2Device. Modelled on
// Chromium's V4L2CaptureDevice (media/capture/video/linux).
//
// Semantics are exactly those of the system calls: a return of -1 sets errno.

#include <poll.h>
#include <sys/types.h>

#include <cstddef>
#include <memory>
#include <string>

namespace garmcap::capture {

class V4l2Device {
 public:
  virtual ~V4l2Device() = default;
  virtual int open(const std::string& path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  virtual void* mmap(void* start, std::size_t length, int prot, int flags, int fd,
                     off_t offset) = 0;
  virtual int munmap(void* start, std::size_t length) = 0;
  virtual int poll(pollfd* fds, nfds_t count, int timeoutMs) = 0;
};

/// The real thing: ::open, ::ioctl, ::mmap, ... on /dev/videoN.
std::unique_ptr<V4l2Device> makeSystemV4l2Device();

}  // namespace garmcap::capture
