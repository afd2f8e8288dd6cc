#include "garmcap/dsw/csv.h"

#include <cctype>

namespace garmcap::dsw {
namespace {

// Digits with an optional sign and one decimal point: what spreadsheets read as a number and
// never as a formula, so a negative number need not be turned into text.
bool isPlainNumber(const std::string& s) {
  std::size_t i = (s.front() == '-' || s.front() == '+') ? 1 : 0;
  bool digits = false, point = false;
  for (; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (std::isdigit(c)) {
      digits = true;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  return digits;
}

}  // namespace

std::string csvField(const std::string& value) {
  std::string v = value;
  if (!v.empty() && std::string("=+-@\t\r").find(v.front()) != std::string::npos &&
      !isPlainNumber(v))
    v.insert(v.begin(), '\'');
  const bool quote = v.find_first_of(",\"\r\n") != std::string::npos ||
                     (!v.empty() && (v.front() == ' ' || v.back() == ' '));
  if (!quote)
    return v;
  std::string out = "\"";
  for (char c : v) {
    if (c == '"')
      out += '"';
    out += c;
  }
  out += '"';
  return out;
}

}  // namespace garmcap::dsw
