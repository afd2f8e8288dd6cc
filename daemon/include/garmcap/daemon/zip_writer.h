#pragma once
// A ZIP archive (PKWARE APPNOTE 6.3, "stored" method: the catalog's images are JPEG/PNG/WebP
// already) written front to back, so that it can be sent while it is made: each entry's local
// header and bytes as soon as the entry is known, the central directory at the end. An entry
// whose bytes are all at hand gets its CRC-32 (zlib) and sizes in its local header; an entry
// written in pieces (begin/add/end) gets general-purpose flag bit 3 and a data descriptor
// (signature 0x08074b50) after its bytes. The central directory is kept in a SpillBuffer (a
// temporary file past 1 MiB), so the writer's memory does not grow with the entry count.
//
// Zip64 (APPNOTE 4.3.14-4.3.16, 4.5.3) where the plain fields overflow: an entry of 4 GiB or
// more gets the zip64 extra field (0x0001) with both sizes in its local header; a local header
// at offset 4 GiB or more, its offset in the central record's zip64 field; 65,535 entries or
// more, or a central directory past 4 GiB, the zip64 end of central directory record and its
// locator before the end record. An entry written in pieces does not know its size up front:
// without `forceZip64` its data descriptor has 4-byte sizes and it may not reach 4 GiB
// (ExportError); with it, every entry and the end carry the zip64 forms (the plain fields set to
// 0xFFFF... so that a reader must use them), which is what the tests read back.

#include <cstdint>
#include <string>
#include <string_view>

#include "garmcap/daemon/spill_buffer.h"

namespace garmcap::daemon {

class ZipWriter {
 public:
  struct Options {
    bool forceZip64 = false;
  };
  ZipWriter();
  explicit ZipWriter(Options options);

  /// A whole entry: its local header and bytes, to be sent next. Throws ExportError
  /// (export_shop.h) for an empty, absolute, backslashed or "."/".."-containing path.
  std::string file(const std::string& path, std::string_view data);

  /// An entry written in pieces: its local header. Then add() each piece (the caller sends the
  /// piece itself, after this header), then end() for its data descriptor.
  std::string begin(const std::string& path);
  void add(std::string_view piece);
  std::string end();

  /// After the last entry: the central directory and the end records, in pieces of at most
  /// `maxPiece` bytes (the end records in one piece); empty once everything is out.
  std::string tail(std::size_t maxPiece);

  std::uint64_t bytesWritten() const { return written_; }
  std::uint64_t entries() const { return entries_; }

 private:
  struct Open {
    std::string path;
    std::uint64_t offset = 0;
    std::uint64_t size = 0;
    std::uint32_t crc = 0;
  };
  std::string localHeader(const std::string& path, bool descriptor, std::uint32_t crc,
                          std::uint64_t size);
  void centralRecord(const std::string& path, bool descriptor, std::uint32_t crc,
                     std::uint64_t size, std::uint64_t offset);
  std::string endRecords();

  Options options_;
  std::uint64_t written_ = 0;
  std::uint64_t entries_ = 0;
  bool inEntry_ = false;
  Open open_;
  SpillBuffer central_;
  enum class Tail { kNotStarted, kCentral, kDone } tail_ = Tail::kNotStarted;
  std::uint64_t centralOffset_ = 0;
};

/// The CRC-32 ZIP uses (zlib's crc32), continued from `crc` (0 to start).
std::uint32_t zipCrc32(std::string_view data, std::uint32_t crc = 0);

}  // namespace garmcap::daemon
