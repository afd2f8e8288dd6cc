#pragma once
// A ZIP archive (PKWARE APPNOTE 6.3, "stored" method, no compression: the catalog's images are
// JPEG/PNG already) built in memory, CRC-32 computed here. Pure function, thread-safe.

#include <string>
#include <vector>

namespace garmcap::daemon {

struct ZipEntry {
  std::string path;  // relative, '/'-separated, UTF-8 (flagged as such), e.g. "images/a.jpg"
  std::string data;  // file bytes
};

/// The archive's bytes. Throws ExportError (export_shop.h) for an empty, absolute, duplicate
/// or ".."-containing path, or an archive past the 4 GiB / 65535-entry limits of plain ZIP.
std::string storeZip(const std::vector<ZipEntry>& entries);

}  // namespace garmcap::daemon
