#include "garmcap/daemon/export_zip.h"

#include <set>

#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/zip_writer.h"

namespace garmcap::daemon {

std::string storeZip(const std::vector<ZipEntry>& entries) {
  std::set<std::string> seen;
  for (const auto& e : entries)
    if (!seen.insert(e.path).second)
      throw ExportError("zip: duplicate entry path '" + e.path + "'");
  ZipWriter zip;
  std::string out;
  for (const auto& e : entries)
    out += zip.file(e.path, e.data);
  for (std::string piece; !(piece = zip.tail(1 << 20)).empty();)
    out += piece;
  return out;
}

}  // namespace garmcap::daemon
