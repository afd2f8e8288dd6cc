#include "garmcap/daemon/spill_buffer.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace garmcap::daemon {

namespace {
std::runtime_error ioError(const char* what) {
  return std::runtime_error(std::string("temporary file: ") + what + ": " + std::strerror(errno));
}
}  // namespace

SpillBuffer::SpillBuffer(std::size_t memoryLimit) : memoryLimit_(memoryLimit) {}

SpillBuffer::~SpillBuffer() {
  if (file_)
    std::fclose(file_);
}

void SpillBuffer::append(std::string_view bytes) {
  if (reading_)
    throw std::logic_error("SpillBuffer: append after reading started");
  size_ += bytes.size();
  if (!file_ && memory_.size() + bytes.size() <= memoryLimit_) {
    memory_.append(bytes);
    return;
  }
  if (!file_) {
    file_ = std::tmpfile();
    if (!file_)
      throw ioError("cannot create one");
    if (!memory_.empty() && std::fwrite(memory_.data(), 1, memory_.size(), file_) != memory_.size())
      throw ioError("cannot write");
    std::string().swap(memory_);
  }
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    throw ioError("cannot write");
}

void SpillBuffer::rewind() {
  reading_ = true;
  readAt_ = 0;
  if (file_ && std::fseek(file_, 0, SEEK_SET) != 0)
    throw ioError("cannot seek");
}

std::string SpillBuffer::read(std::size_t maxBytes) {
  if (!reading_)
    rewind();
  const std::size_t n = std::min(maxBytes, size_ - readAt_);
  std::string out;
  if (n == 0)
    return out;
  if (!file_) {
    out = memory_.substr(readAt_, n);
  } else {
    out.resize(n);
    if (std::fread(out.data(), 1, n, file_) != n)
      throw ioError("cannot read back");
  }
  readAt_ += n;
  return out;
}

}  // namespace garmcap::daemon
