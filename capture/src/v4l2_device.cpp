#include "garmcap/capture/v4l2_device.h"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace garmcap::capture {
namespace {

class SystemV4l2Device final : public V4l2Device {
 public:
  int open(const std::string& path, int flags) override { return ::open(path.c_str(), flags); }
  int close(int fd) override { return ::close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override { return ::ioctl(fd, request, arg); }
  void* mmap(void* start, std::size_t length, int prot, int flags, int fd, off_t offset) override {
    return ::mmap(start, length, prot, flags, fd, offset);
  }
  int munmap(void* start, std::size_t length) override { return ::munmap(start, length); }
  int poll(pollfd* fds, nfds_t count, int timeoutMs) override {
    return ::poll(fds, count, timeoutMs);
  }
};

}  // namespace

std::unique_ptr<V4l2Device> makeSystemV4l2Device() {
  return std::make_unique<SystemV4l2Device>();
}

}  // namespace garmcap::capture
