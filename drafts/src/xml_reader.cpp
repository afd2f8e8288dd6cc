#include "xml_reader.h"

#include <algorithm>
#include <cstdint>
#include <tuple>

#include "garmcap/drafts/file_io.h"

namespace garmcap::drafts::detail {

namespace {

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

bool isNameStart(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':' || u >= 0x80;
}

bool isNameChar(char c) {
  return isNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
}

void appendUtf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& what) : s_(text), what_(what) {
    lineStarts_.push_back(0);
    for (size_t i = 0; i < s_.size(); ++i) {
      if (s_[i] == '\n')
        lineStarts_.push_back(i + 1);
    }
  }

  XmlElement document() {
    if (s_.substr(0, 3) == "\xEF\xBB\xBF")
      pos_ = 3;  // UTF-8 byte order mark
    skipMisc(true);
    if (pos_ >= s_.size() || s_[pos_] != '<')
      fail("expected the root element");
    XmlElement root = element(1);
    skipMisc(false);
    if (pos_ < s_.size())
      fail("content after the root element '" + root.name + "'");
    return root;
  }

 private:
  [[noreturn]] void failAt(size_t at, const std::string& reason) const {
    const auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), at);
    const size_t line = size_t(it - lineStarts_.begin());
    const size_t column = at - lineStarts_[line - 1] + 1;
    throw ParseError(what_ + ": line " + std::to_string(line) + ", column " +
                     std::to_string(column) + ": " + reason);
  }
  [[noreturn]] void fail(const std::string& reason) const { failAt(pos_, reason); }

  std::pair<int, int> lineColumn(size_t at) const {
    const auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), at);
    const size_t line = size_t(it - lineStarts_.begin());
    return {int(line), int(at - lineStarts_[line - 1] + 1)};
  }

  bool startsWith(std::string_view prefix) const {
    return s_.substr(pos_, prefix.size()) == prefix;
  }

  void expect(std::string_view token, const char* context) {
    if (!startsWith(token)) {
      fail("expected '" + std::string(token) + "' " + context);
    }
    pos_ += token.size();
  }

  void skipSpace() {
    while (pos_ < s_.size() && isSpace(s_[pos_]))
      ++pos_;
  }

  // Skips `until` after the current position, failing with `what` when it never comes.
  void skipPast(std::string_view until, const char* construct) {
    const size_t start = pos_;
    const size_t end = s_.find(until, pos_);
    if (end == std::string_view::npos)
      failAt(start, std::string("unterminated ") + construct);
    pos_ = end + until.size();
  }

  // Whitespace, comments, processing instructions and (before the root) a DOCTYPE.
  void skipMisc(bool prolog) {
    for (;;) {
      skipSpace();
      if (startsWith("<!--")) {
        pos_ += 4;
        skipPast("-->", "comment");
      } else if (startsWith("<?")) {
        pos_ += 2;
        skipPast("?>", "processing instruction");
      } else if (prolog && startsWith("<!DOCTYPE")) {
        const size_t start = pos_;
        const size_t gt = s_.find('>', pos_);
        const size_t bracket = s_.find('[', pos_);
        if (bracket != std::string_view::npos && (gt == std::string_view::npos || bracket < gt)) {
          failAt(start, "DOCTYPE with an internal subset is not accepted");
        }
        if (gt == std::string_view::npos)
          failAt(start, "unterminated DOCTYPE");
        pos_ = gt + 1;
      } else {
        return;
      }
    }
  }

  std::string name() {
    const size_t start = pos_;
    if (pos_ >= s_.size() || !isNameStart(s_[pos_]))
      fail("expected a name");
    while (pos_ < s_.size() && isNameChar(s_[pos_]))
      ++pos_;
    return std::string(s_.substr(start, pos_ - start));
  }

  // Decodes an entity reference starting at '&'; appends it to `out`.
  void entity(std::string& out) {
    const size_t start = pos_;
    const size_t semi = s_.find(';', pos_);
    if (semi == std::string_view::npos || semi - pos_ > 12)
      failAt(start, "unterminated entity reference");
    const std::string_view ref = s_.substr(pos_ + 1, semi - pos_ - 1);
    pos_ = semi + 1;
    if (ref == "lt")
      out += '<';
    else if (ref == "gt")
      out += '>';
    else if (ref == "amp")
      out += '&';
    else if (ref == "quot")
      out += '"';
    else if (ref == "apos")
      out += '\'';
    else if (ref.size() >= 2 && ref[0] == '#') {
      const bool hex = ref[1] == 'x';
      const std::string_view digits = ref.substr(hex ? 2 : 1);
      if (digits.empty())
        failAt(start, "empty character reference");
      std::uint32_t cp = 0;
      for (char c : digits) {
        int d = -1;
        if (c >= '0' && c <= '9')
          d = c - '0';
        else if (hex && c >= 'a' && c <= 'f')
          d = c - 'a' + 10;
        else if (hex && c >= 'A' && c <= 'F')
          d = c - 'A' + 10;
        if (d < 0)
          failAt(start, "bad character reference '&" + std::string(ref) + ";'");
        cp = cp * (hex ? 16 : 10) + std::uint32_t(d);
        if (cp > 0x10FFFF)
          failAt(start, "character reference out of range");
      }
      if (cp == 0 || (cp >= 0xD800 && cp <= 0xDFFF))
        failAt(start, "invalid character reference");
      appendUtf8(out, cp);
    } else {
      failAt(start, "unknown entity '&" + std::string(ref) + ";'");
    }
  }

  std::string attributeValue() {
    if (pos_ >= s_.size() || (s_[pos_] != '"' && s_[pos_] != '\''))
      fail("expected a quoted attribute value");
    const char quote = s_[pos_++];
    const size_t start = pos_;
    std::string value;
    for (;;) {
      if (pos_ >= s_.size())
        failAt(start - 1, "unterminated attribute value");
      const char c = s_[pos_];
      if (c == quote) {
        ++pos_;
        return value;
      }
      if (c == '<')
        fail("'<' in an attribute value");
      if (c == '&') {
        entity(value);
        continue;
      }
      // Attribute-value normalisation of the XML spec: white space characters become spaces.
      value += (c == '\t' || c == '\n' || c == '\r') ? ' ' : c;
      ++pos_;
    }
  }

  XmlElement element(int depth) {
    if (depth > kMaxXmlDepth)
      fail("elements nested deeper than " + std::to_string(kMaxXmlDepth));
    XmlElement e;
    std::tie(e.line, e.column) = lineColumn(pos_);
    expect("<", "to open an element");
    e.name = name();
    for (;;) {
      const size_t before = pos_;
      skipSpace();
      if (startsWith("/>")) {
        pos_ += 2;
        return e;
      }
      if (startsWith(">")) {
        ++pos_;
        break;
      }
      if (pos_ == before)
        fail("expected whitespace, '>' or '/>' in element '" + e.name + "'");
      const size_t attrAt = pos_;
      std::string attr = name();
      skipSpace();
      expect("=", "after an attribute name");
      skipSpace();
      std::string value = attributeValue();
      if (e.attribute(attr))
        failAt(attrAt, "duplicate attribute '" + attr + "' in element '" + e.name + "'");
      e.attributes.emplace_back(std::move(attr), std::move(value));
    }
    // Content.
    for (;;) {
      if (pos_ >= s_.size())
        fail("element '" + e.name + "' (line " + std::to_string(e.line) + ") is not closed");
      if (startsWith("</")) {
        pos_ += 2;
        const size_t nameAt = pos_;
        const std::string end = name();
        if (end != e.name) {
          failAt(nameAt, "end tag '" + end + "' does not match '" + e.name + "' opened at line " +
                             std::to_string(e.line));
        }
        skipSpace();
        expect(">", "to close the end tag");
        return e;
      }
      if (startsWith("<!--")) {
        pos_ += 4;
        skipPast("-->", "comment");
      } else if (startsWith("<![CDATA[")) {
        pos_ += 9;
        const size_t start = pos_;
        skipPast("]]>", "CDATA section");
        e.text.append(s_.substr(start, pos_ - 3 - start));
      } else if (startsWith("<?")) {
        pos_ += 2;
        skipPast("?>", "processing instruction");
      } else if (startsWith("<")) {
        e.children.push_back(element(depth + 1));
      } else if (s_[pos_] == '&') {
        entity(e.text);
      } else {
        e.text += s_[pos_++];
      }
    }
  }

  std::string_view s_;
  const std::string& what_;
  size_t pos_ = 0;
  std::vector<size_t> lineStarts_;
};

}  // namespace

const std::string* XmlElement::attribute(std::string_view attr) const {
  for (const auto& [k, v] : attributes) {
    if (k == attr)
      return &v;
  }
  return nullptr;
}

const XmlElement* XmlElement::child(std::string_view childName) const {
  for (const auto& c : children) {
    if (c.name == childName)
      return &c;
  }
  return nullptr;
}

XmlElement parseXml(std::string_view text, const std::string& what) {
  return Parser(text, what).document();
}

}  // namespace garmcap::drafts::detail
