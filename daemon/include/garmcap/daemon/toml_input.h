#pragma once
// TOML text from outside (the station's and the hub's configuration files) as toml11's document.
//
// toml11 3.7.1 (Debian bookworm) parses recursively and without limits, and tests/fuzz's
// fuzz_config_toml found inputs that crash or hang it before any of our checks could run: arrays
// or inline tables nested 200,000 deep overflow the stack (garmcapd died with SIGSEGV at start),
// a binary integer of 63 or more digits overflows a signed integer inside parse_binary_integer
// (undefined behaviour), dotted keys and table headers of 200,000 parts take minutes (the parser
// is quadratic in them), and invalid UTF-8 makes its literal-string reader read past its buffer.
// A configuration never needs any of these, so the text is checked first and refused with the
// line that breaks the limit.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <toml.hpp>

namespace garmcap::daemon {

/// Thrown for text that is not valid TOML or that breaks one of the limits below; the message
/// names the line (toml11's own messages carry it too) and never quotes the input unescaped.
class TomlInputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Arrays, inline tables and table headers nested deeper than this are refused.
inline constexpr std::size_t kMaxTomlNesting = 32;
/// Dotted keys and table headers with more parts than this are refused.
inline constexpr std::size_t kMaxTomlKeyParts = 32;
/// Binary integers with more digits than this are refused (toml11 3.7.1 overflows at 63).
inline constexpr std::size_t kMaxTomlBinaryDigits = 62;

/// The text parsed, or TomlInputError. `name` is the file name toml11 puts in its messages.
toml::value parseTomlText(const std::string& text, const std::string& name);

}  // namespace garmcap::daemon
