#pragma once
// Bytes appended now and read back later, in order, that must not take memory in proportion
// to their size: a ZIP's central directory (one record per entry, written at the end) and
// catalog.zip's notes (its README, written last). Held in memory up to `memoryLimit`, then
// moved to an anonymous temporary file (std::tmpfile: deleted when closed, or when the process
// ends). Not thread-safe; one writer, then one reader.

#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

namespace garmcap::daemon {

class SpillBuffer {
 public:
  explicit SpillBuffer(std::size_t memoryLimit = 1 << 20);
  ~SpillBuffer();
  SpillBuffer(const SpillBuffer&) = delete;
  SpillBuffer& operator=(const SpillBuffer&) = delete;

  /// Appends; throws std::runtime_error when the temporary file cannot be made or written.
  void append(std::string_view bytes);
  std::size_t size() const { return size_; }
  /// Reading starts again at the first byte.
  void rewind();
  /// The next bytes, at most `maxBytes`; empty at the end. Throws std::runtime_error on a read
  /// error.
  std::string read(std::size_t maxBytes);

 private:
  std::size_t memoryLimit_;
  std::string memory_;
  std::FILE* file_ = nullptr;
  std::size_t size_ = 0;
  std::size_t readAt_ = 0;
  bool reading_ = false;
};

}  // namespace garmcap::daemon
