#include "garmcap/daemon/zip_writer.h"

#include <zlib.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "garmcap/daemon/export_shop.h"

namespace garmcap::daemon {

namespace {

constexpr std::uint32_t kDosTime = 0;                            // 00:00:00
constexpr std::uint32_t kDosDate = (46u << 9) | (1u << 5) | 1u;  // 2026-01-01: reproducible bytes
constexpr std::uint32_t kUtf8Flag = 1u << 11;
constexpr std::uint32_t kDescriptorFlag = 1u << 3;
constexpr std::uint32_t kVersionPlain = 20;  // 2.0: stored files, folders
constexpr std::uint32_t kVersionZip64 = 45;  // 4.5: zip64 extensions
constexpr std::uint32_t kMadeByUnix = 3u << 8;
constexpr std::uint64_t kMax32 = 0xffffffffu;
constexpr std::uint64_t kMax16 = 0xffffu;

void put16(std::string& out, std::uint64_t v) {
  out += static_cast<char>(v & 0xff);
  out += static_cast<char>((v >> 8) & 0xff);
}
void put32(std::string& out, std::uint64_t v) {
  put16(out, v & 0xffff);
  put16(out, (v >> 16) & 0xffff);
}
void put64(std::string& out, std::uint64_t v) {
  put32(out, v & kMax32);
  put32(out, v >> 32);
}

void checkPath(const std::string& p) {
  if (p.empty() || p.front() == '/' || p.find('\\') != std::string::npos)
    throw ExportError("zip: bad entry path '" + p + "' (empty, absolute or with a backslash)");
  if (p.size() > kMax16)
    throw ExportError("zip: entry path longer than 65,535 bytes");
  size_t start = 0;
  while (start <= p.size()) {
    size_t end = p.find('/', start);
    if (end == std::string::npos)
      end = p.size();
    const std::string_view part(p.data() + start, end - start);
    if (part.empty() || part == "." || part == "..")
      throw ExportError("zip: bad entry path '" + p + "' (empty, '.' or '..' component)");
    start = end + 1;
  }
}

}  // namespace

std::uint32_t zipCrc32(std::string_view data, std::uint32_t crc) {
  uLong c = crc;
  const auto* bytes = reinterpret_cast<const Bytef*>(data.data());
  // zlib takes a uInt length: feed it at most 1 GiB at a time.
  for (std::size_t at = 0; at < data.size();) {
    const std::size_t n = std::min<std::size_t>(data.size() - at, 1u << 30);
    c = ::crc32(c, bytes + at, static_cast<uInt>(n));
    at += n;
  }
  return static_cast<std::uint32_t>(c);
}

ZipWriter::ZipWriter() : ZipWriter(Options{}) {}
ZipWriter::ZipWriter(Options options) : options_(options) {}

std::string ZipWriter::localHeader(const std::string& path, bool descriptor, std::uint32_t crc,
                                   std::uint64_t size) {
  // A descriptor entry's sizes and CRC are zero here (APPNOTE 4.4.4); with zip64 its sizes are
  // 0xFFFFFFFF and the extra field holds the (zero) 8-byte sizes, which tells a reader that the
  // data descriptor's sizes are 8 bytes each (4.3.9.2).
  const bool zip64 = options_.forceZip64 || (!descriptor && size >= kMax32);
  std::string h;
  put32(h, 0x04034b50);
  put16(h, zip64 ? kVersionZip64 : kVersionPlain);
  put16(h, kUtf8Flag | (descriptor ? kDescriptorFlag : 0));
  put16(h, 0);  // stored
  put16(h, kDosTime);
  put16(h, kDosDate);
  put32(h, descriptor ? 0 : crc);
  put32(h, zip64 ? kMax32 : descriptor ? 0 : size);
  put32(h, zip64 ? kMax32 : descriptor ? 0 : size);
  put16(h, path.size());
  put16(h, zip64 ? 20 : 0);
  h += path;
  if (zip64) {
    put16(h, 0x0001);
    put16(h, 16);
    put64(h, descriptor ? 0 : size);  // original size
    put64(h, descriptor ? 0 : size);  // compressed size (stored: the same)
  }
  return h;
}

void ZipWriter::centralRecord(const std::string& path, bool descriptor, std::uint32_t crc,
                              std::uint64_t size, std::uint64_t offset) {
  // The zip64 extra field holds only the fields whose plain value is 0xFFFFFFFF, in the order
  // original size, compressed size, local header offset (4.5.3).
  const bool bigSize = options_.forceZip64 || size >= kMax32;
  const bool bigOffset = options_.forceZip64 || offset >= kMax32;
  std::string extra;
  if (bigSize || bigOffset) {
    put16(extra, 0x0001);
    put16(extra, (bigSize ? 16 : 0) + (bigOffset ? 8 : 0));
    if (bigSize) {
      put64(extra, size);
      put64(extra, size);
    }
    if (bigOffset)
      put64(extra, offset);
  }
  const bool zip64 = !extra.empty() || options_.forceZip64;
  std::string r;
  put32(r, 0x02014b50);
  put16(r, kMadeByUnix | (zip64 ? kVersionZip64 : kVersionPlain));
  put16(r, zip64 ? kVersionZip64 : kVersionPlain);
  put16(r, kUtf8Flag | (descriptor ? kDescriptorFlag : 0));
  put16(r, 0);
  put16(r, kDosTime);
  put16(r, kDosDate);
  put32(r, crc);
  put32(r, bigSize ? kMax32 : size);
  put32(r, bigSize ? kMax32 : size);
  put16(r, path.size());
  put16(r, extra.size());
  put16(r, 0);               // comment
  put16(r, 0);               // disk
  put16(r, 0);               // internal attributes
  put32(r, 0100644u << 16);  // external: regular file rw-r--r--
  put32(r, bigOffset ? kMax32 : offset);
  r += path;
  r += extra;
  central_.append(r);
  ++entries_;
}

std::string ZipWriter::file(const std::string& path, std::string_view data) {
  if (inEntry_ || tail_ != Tail::kNotStarted)
    throw std::logic_error("ZipWriter::file inside an entry or after the end");
  checkPath(path);
  const std::uint32_t crc = zipCrc32(data);
  std::string out = localHeader(path, false, crc, data.size());
  centralRecord(path, false, crc, data.size(), written_);
  out += data;
  written_ += out.size();
  return out;
}

std::string ZipWriter::begin(const std::string& path) {
  if (inEntry_ || tail_ != Tail::kNotStarted)
    throw std::logic_error("ZipWriter::begin inside an entry or after the end");
  checkPath(path);
  inEntry_ = true;
  open_ = Open{path, written_, 0, 0};
  std::string h = localHeader(path, true, 0, 0);
  written_ += h.size();
  return h;
}

void ZipWriter::add(std::string_view piece) {
  if (!inEntry_)
    throw std::logic_error("ZipWriter::add outside an entry");
  open_.crc = zipCrc32(piece, open_.crc);
  open_.size += piece.size();
  written_ += piece.size();
  if (!options_.forceZip64 && open_.size >= kMax32)
    throw ExportError("zip: " + open_.path + " reached 4 GiB, past what its data descriptor holds");
}

std::string ZipWriter::end() {
  if (!inEntry_)
    throw std::logic_error("ZipWriter::end outside an entry");
  inEntry_ = false;
  std::string d;
  put32(d, 0x08074b50);
  put32(d, open_.crc);
  if (options_.forceZip64) {
    put64(d, open_.size);
    put64(d, open_.size);
  } else {
    put32(d, open_.size);
    put32(d, open_.size);
  }
  centralRecord(open_.path, true, open_.crc, open_.size, open_.offset);
  written_ += d.size();
  return d;
}

std::string ZipWriter::endRecords() {
  const std::uint64_t cdSize = central_.size();
  const std::uint64_t cdOffset = centralOffset_;
  const bool zip64 =
      options_.forceZip64 || entries_ >= kMax16 || cdSize >= kMax32 || cdOffset >= kMax32;
  std::string out;
  if (zip64) {
    const std::uint64_t recordOffset = cdOffset + cdSize;
    put32(out, 0x06064b50);  // zip64 end of central directory record
    put64(out, 44);          // its size after this field
    put16(out, kMadeByUnix | kVersionZip64);
    put16(out, kVersionZip64);
    put32(out, 0);  // this disk
    put32(out, 0);  // the disk with the central directory
    put64(out, entries_);
    put64(out, entries_);
    put64(out, cdSize);
    put64(out, cdOffset);
    put32(out, 0x07064b50);  // its locator
    put32(out, 0);           // the disk with the zip64 end record
    put64(out, recordOffset);
    put32(out, 1);  // disks in all
  }
  // Forced: every field the zip64 record holds is 0xFFFF... here, so a reader must take it.
  const bool force = options_.forceZip64;
  put32(out, 0x06054b50);
  put16(out, 0);
  put16(out, 0);
  put16(out, force || entries_ >= kMax16 ? kMax16 : entries_);
  put16(out, force || entries_ >= kMax16 ? kMax16 : entries_);
  put32(out, force || cdSize >= kMax32 ? kMax32 : cdSize);
  put32(out, force || cdOffset >= kMax32 ? kMax32 : cdOffset);
  put16(out, 0);  // comment
  return out;
}

std::string ZipWriter::tail(std::size_t maxPiece) {
  if (inEntry_)
    throw std::logic_error("ZipWriter::tail inside an entry");
  if (tail_ == Tail::kNotStarted) {
    tail_ = Tail::kCentral;
    centralOffset_ = written_;
    central_.rewind();
  }
  if (tail_ == Tail::kDone)
    return {};
  std::string piece = central_.read(std::max<std::size_t>(maxPiece, 1));
  if (piece.empty()) {
    written_ += central_.size();
    tail_ = Tail::kDone;
    piece = endRecords();
    written_ += piece.size();
  }
  return piece;
}

}  // namespace garmcap::daemon
