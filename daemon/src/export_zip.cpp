#include "garmcap/daemon/export_zip.h"

#include <array>
#include <cstdint>
#include <limits>
#include <set>

#include "garmcap/daemon/export_shop.h"

namespace garmcap::daemon {
namespace {

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320) as ZIP requires.
uint32_t crc32Of(const std::string& data) {
  static const auto kTable = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k)
        c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xffffffffu;
  for (unsigned char b : data)
    c = kTable[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

void put16(std::string& out, uint32_t v) {
  out += static_cast<char>(v & 0xff);
  out += static_cast<char>((v >> 8) & 0xff);
}
void put32(std::string& out, uint32_t v) {
  put16(out, v & 0xffff);
  put16(out, v >> 16);
}

void checkPath(const std::string& p, std::set<std::string>& seen) {
  if (p.empty() || p.front() == '/' || p.find('\\') != std::string::npos)
    throw ExportError("zip: bad entry path '" + p + "' (empty, absolute or with a backslash)");
  size_t start = 0;
  while (start <= p.size()) {
    size_t end = p.find('/', start);
    if (end == std::string::npos)
      end = p.size();
    std::string part = p.substr(start, end - start);
    if (part.empty() || part == "." || part == "..")
      throw ExportError("zip: bad entry path '" + p + "' (empty, '.' or '..' component)");
    start = end + 1;
  }
  if (!seen.insert(p).second)
    throw ExportError("zip: duplicate entry path '" + p + "'");
}

}  // namespace

std::string storeZip(const std::vector<ZipEntry>& entries) {
  constexpr uint32_t kDosTime = 0;                            // 00:00:00
  constexpr uint32_t kDosDate = (46u << 9) | (1u << 5) | 1u;  // 2026-01-01: reproducible bytes
  constexpr uint32_t kUtf8Flag = 1u << 11;
  if (entries.size() >= 0xffff)
    throw ExportError("zip: too many entries for plain ZIP");
  std::set<std::string> seen;
  std::string out, central;
  for (const auto& e : entries) {
    checkPath(e.path, seen);
    if (out.size() + e.data.size() + e.path.size() + 64 >= std::numeric_limits<uint32_t>::max())
      throw ExportError("zip: archive would exceed 4 GiB (plain ZIP limit)");
    const uint32_t crc = crc32Of(e.data);
    const uint32_t size = static_cast<uint32_t>(e.data.size());
    const uint32_t offset = static_cast<uint32_t>(out.size());
    // Local file header.
    put32(out, 0x04034b50);
    put16(out, 20);  // version needed: 2.0
    put16(out, kUtf8Flag);
    put16(out, 0);  // stored
    put16(out, kDosTime);
    put16(out, kDosDate);
    put32(out, crc);
    put32(out, size);
    put32(out, size);
    put16(out, static_cast<uint32_t>(e.path.size()));
    put16(out, 0);
    out += e.path;
    out += e.data;
    // Central directory record.
    put32(central, 0x02014b50);
    put16(central, (3u << 8) | 20);  // made by: UNIX, 2.0
    put16(central, 20);
    put16(central, kUtf8Flag);
    put16(central, 0);
    put16(central, kDosTime);
    put16(central, kDosDate);
    put32(central, crc);
    put32(central, size);
    put32(central, size);
    put16(central, static_cast<uint32_t>(e.path.size()));
    put16(central, 0);               // extra
    put16(central, 0);               // comment
    put16(central, 0);               // disk
    put16(central, 0);               // internal attributes
    put32(central, 0100644u << 16);  // external: regular file rw-r--r--
    put32(central, offset);
    central += e.path;
  }
  const uint32_t cdOffset = static_cast<uint32_t>(out.size());
  out += central;
  put32(out, 0x06054b50);
  put16(out, 0);
  put16(out, 0);
  put16(out, static_cast<uint32_t>(entries.size()));
  put16(out, static_cast<uint32_t>(entries.size()));
  put32(out, static_cast<uint32_t>(central.size()));
  put32(out, cdOffset);
  put16(out, 0);
  return out;
}

}  // namespace garmcap::daemon
