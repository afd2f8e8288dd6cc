#pragma once
// UTF-8 checks for text that comes from outside (HTTP requests, the configuration file) and the
// one way such text is quoted back in an error message.

#include <cstddef>
#include <string>
#include <string_view>

namespace garmcap::daemon {

/// True when `s` is well-formed UTF-8 (no overlong forms, no surrogates, nothing past U+10FFFF).
bool validUtf8(std::string_view s);

/// `s` made safe to quote in an error message: invalid UTF-8 bytes and control characters as
/// \xNN, and cut (at a character boundary, with "...") after `maxBytes`.
std::string quoteInput(std::string_view s, std::size_t maxBytes = 64);

}  // namespace garmcap::daemon
