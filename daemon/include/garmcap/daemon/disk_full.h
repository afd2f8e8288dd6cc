#pragma once
// The station's disk is full: what the catalog (SQLITE_FULL, or an I/O error with ENOSPC) and the
// image store (ENOSPC, EDQUOT) throw instead of their usual errors, so that every caller can tell
// staff the one thing to do (free space) and answer HTTP 507 instead of a 400 or a 500 with SQL.
// Nothing is changed by the failed write: SQLite rolls the transaction back, the store removes
// its temporary file.

#include <stdexcept>
#include <string>

namespace garmcap::daemon {

class DiskFull : public std::runtime_error {
 public:
  explicit DiskFull(const std::string& where)
      : std::runtime_error("the station's disk is full (" + where +
                           "): nothing was changed; free space in the station's data folder "
                           "and try again") {}
};

}  // namespace garmcap::daemon
