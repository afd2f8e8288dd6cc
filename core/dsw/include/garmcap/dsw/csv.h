#pragma once
// CSV cells, the one definition every CSV writer of the station uses (size guides, shop
// exports): RFC 4180 quoting plus the spreadsheet formula guard.

#include <string>

namespace garmcap::dsw {

/// One CSV cell. A value holding a comma, quote, CR or LF, or with a leading or trailing space,
/// is quoted with inner quotes doubled (RFC 4180). A text starting with '=', '+', '-', '@', tab
/// or CR gets a leading apostrophe first, so that a spreadsheet shows it as text instead of
/// running it as a formula; a plain number ("-1", "-0.5") is left as it is.
std::string csvField(const std::string& value);

}  // namespace garmcap::dsw
