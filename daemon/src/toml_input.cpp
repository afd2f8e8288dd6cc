#include "garmcap/daemon/toml_input.h"

#include <optional>
#include <sstream>

#include "garmcap/daemon/utf8.h"

namespace garmcap::daemon {
namespace {

bool startsWith(std::string_view s, std::size_t at, std::string_view prefix) {
  return s.substr(at, prefix.size()) == prefix;
}

bool isBareChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-' || c == '+' || c == '.' || c == ':';
}

enum class State { Plain, Comment, Basic, Literal, MultiBasic, MultiLiteral };

// Inside a multi-line string, at a run of `quote`: how many characters after `at` the run takes,
// and whether it ends the string. TOML lets up to two quotes of the content stand right before
// the closing three (four quotes are a quote and the end), so the string ends at the run's last
// three, not its first. Closing at the first left a stray quote that opened a string toml11 never
// saw, and the brackets after it went uncounted (fuzz_config_toml: a stack overflow again).
std::size_t closingQuotes(std::string_view s, std::size_t at, char quote, State& state) {
  std::size_t run = 0;
  while (at + run < s.size() && s[at + run] == quote)
    ++run;
  if (run >= 3)
    state = State::Plain;
  return run - 1;
}

// The first place the text breaks a limit, as "line N: what". A small lexer of its own: it only
// has to know where strings and comments are, so brackets, dots and digits inside them are not
// counted; anything else malformed is left to toml11, which refuses it without recursing further
// than the limits allow.
std::optional<std::string> firstLimitBroken(std::string_view s) {
  State state = State::Plain;
  std::size_t line = 1;
  std::size_t depth = 0;
  std::size_t dots = 0;  // dots since the last '=', ',', bracket or newline: a key's parts - 1
  const auto at = [&line](const std::string& what) {
    return "line " + std::to_string(line) + ": " + what;
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\n')
      ++line;
    switch (state) {
      case State::Comment:
        if (c == '\n')
          state = State::Plain;
        break;
      case State::Basic:
      case State::MultiBasic:
        if (c == '\\' && i + 1 < s.size()) {
          if (s[i + 1] == '\n')
            ++line;
          ++i;
        } else if (state == State::Basic && (c == '"' || c == '\n')) {
          state = State::Plain;
        } else if (state == State::MultiBasic && c == '"') {
          i += closingQuotes(s, i, '"', state);
        }
        break;
      case State::Literal:
        if (c == '\'' || c == '\n')
          state = State::Plain;
        break;
      case State::MultiLiteral:
        if (c == '\'')
          i += closingQuotes(s, i, '\'', state);
        break;
      case State::Plain:
        if (c == '#') {
          state = State::Comment;
        } else if (c == '"') {
          state = startsWith(s, i, R"(""")") ? State::MultiBasic : State::Basic;
          i += state == State::MultiBasic ? 2 : 0;
        } else if (c == '\'') {
          state = startsWith(s, i, "'''") ? State::MultiLiteral : State::Literal;
          i += state == State::MultiLiteral ? 2 : 0;
        } else if (c == '[' || c == '{') {
          dots = 0;
          if (++depth > kMaxTomlNesting)
            return at("arrays, inline tables or table headers nested deeper than " +
                      std::to_string(kMaxTomlNesting));
        } else if (c == ']' || c == '}') {
          dots = 0;
          depth -= depth > 0 ? 1 : 0;
        } else if (c == '=' || c == ',' || c == '\n') {
          dots = 0;
        } else if (c == '.') {
          if (++dots >= kMaxTomlKeyParts)
            return at("a dotted key or table header of more than " +
                      std::to_string(kMaxTomlKeyParts) + " parts");
        } else if (c == '0' && i + 1 < s.size() && s[i + 1] == 'b' &&
                   (i == 0 || !isBareChar(s[i - 1]))) {
          std::size_t digits = 0;
          std::size_t j = i + 2;
          for (; j < s.size() && (s[j] == '0' || s[j] == '1' || s[j] == '_'); ++j)
            digits += s[j] != '_' ? 1 : 0;
          if (digits > kMaxTomlBinaryDigits)
            return at("a binary integer of " + std::to_string(digits) + " digits (at most " +
                      std::to_string(kMaxTomlBinaryDigits) + ")");
          i = j - 1;
        }
        break;
    }
  }
  return std::nullopt;
}

}  // namespace

toml::value parseTomlText(const std::string& text, const std::string& name) {
  if (!validUtf8(text))
    throw TomlInputError("not valid UTF-8 (TOML files are UTF-8)");
  if (auto broken = firstLimitBroken(text))
    throw TomlInputError(*broken);
  try {
    std::istringstream stream(text);
    return toml::parse(stream, name);
  } catch (const std::exception& e) {
    throw TomlInputError(e.what());
  }
}

}  // namespace garmcap::daemon
