#pragma once
// Private: a small, strict XML reader for the station's XML inputs (Valentina .vit files). It
// parses elements, attributes, character data, CDATA, comments, processing instructions and
// the predefined and numeric character entities, and reports every error with the line and
// column. It refuses DTD internal subsets (no entity expansion) and nesting deeper than
// kMaxXmlDepth. Namespaces are not interpreted (prefixed names are kept as written).

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace garmcap::drafts::detail {

inline constexpr int kMaxXmlDepth = 200;

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  // in document order, decoded
  std::vector<XmlElement> children;
  std::string text;  // character data directly inside this element, decoded, concatenated
  int line = 0;      // position of the '<' that opens the element (1-based)
  int column = 0;

  /// Attribute value, or nullptr when absent.
  const std::string* attribute(std::string_view attr) const;
  /// First child element with that name, or nullptr.
  const XmlElement* child(std::string_view childName) const;
};

/// Parses a whole document and returns its root element. Throws ParseError
/// "<what>: line L, column C: <reason>".
XmlElement parseXml(std::string_view text, const std::string& what);

}  // namespace garmcap::drafts::detail
