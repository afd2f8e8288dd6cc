#pragma once
// A ZIP archive built in memory (the station's catalog.zip): ZipWriter's entries with their
// sizes up front (zip_writer.h), CRC-32 by zlib. Pure function, thread-safe.

#include <string>
#include <vector>

namespace garmcap::daemon {

struct ZipEntry {
  std::string path;  // relative, '/'-separated, UTF-8 (flagged as such), e.g. "images/a.jpg"
  std::string data;  // file bytes
};

/// The archive's bytes, Zip64 where plain ZIP's 4 GiB / 65,535-entry fields overflow. Throws
/// ExportError (export_shop.h) for an empty, absolute, duplicate or ".."-containing path.
std::string storeZip(const std::vector<ZipEntry>& entries);

}  // namespace garmcap::daemon
