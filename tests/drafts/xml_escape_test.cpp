// The one XML/HTML escaping helper every writer of the station uses.

#include "garmcap/drafts/xml_escape.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using garmcap::drafts::xmlEscape;

namespace {

const std::string kFffd = "\xEF\xBF\xBD";

TEST(XmlEscape, MarkupCharactersBecomeEntities) {
  EXPECT_EQ(xmlEscape(""), "");
  EXPECT_EQ(xmlEscape("plain text 123"), "plain text 123");
  EXPECT_EQ(xmlEscape(R"(<a href="x">Tom & Jerry's</a>)"),
            "&lt;a href=&quot;x&quot;&gt;Tom &amp; Jerry&#39;s&lt;/a&gt;");
  // Already escaped text is escaped again: the helper takes text, not markup.
  EXPECT_EQ(xmlEscape("&amp;"), "&amp;amp;");
}

TEST(XmlEscape, WhitespaceAndUtf8PassThrough) {
  EXPECT_EQ(xmlEscape("a\tb\nc\rd"), "a\tb\nc\rd");
  EXPECT_EQ(xmlEscape("jupe évasée · 55 — 한국"), "jupe évasée · 55 — 한국");
  EXPECT_EQ(xmlEscape("\xEF\xBF\xBD"), kFffd);           // U+FFFD itself is allowed
  EXPECT_EQ(xmlEscape("\xEF\xBF\xBC"), "\xEF\xBF\xBC");  // U+FFFC too
}

TEST(XmlEscape, CharactersInvalidInXml10AreReplaced) {
  // Every C0 control but tab, newline and carriage return, including NUL.
  for (int c = 0; c < 0x20; ++c) {
    if (c == '\t' || c == '\n' || c == '\r')
      continue;
    const std::string in = std::string("a") + static_cast<char>(c) + "b";
    EXPECT_EQ(xmlEscape(in), "a" + kFffd + "b") << "control " << c;
  }
  // The noncharacters U+FFFE and U+FFFF (UTF-8 EF BF BE / EF BF BF), also at the very end.
  EXPECT_EQ(xmlEscape("x\xEF\xBF\xBEy"), "x" + kFffd + "y");
  EXPECT_EQ(xmlEscape("x\xEF\xBF\xBF"), "x" + kFffd);
  // A truncated sequence at the end is not mistaken for one.
  EXPECT_EQ(xmlEscape("x\xEF\xBF"), "x\xEF\xBF");
  // DEL is allowed by XML 1.0 and kept.
  EXPECT_EQ(xmlEscape("a\x7F"), "a\x7F");
}

// A real XML 1.0 parser accepts every byte 1..127 (and NUL) once escaped, in an attribute
// quoted either way and in character data.
TEST(XmlEscape, XmllintAcceptsEscapedAsciiEverywhere) {
  if (std::system("command -v xmllint >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "xmllint not installed (station.sh installs libxml2-utils)";
  }
  std::string all(1, '\0');
  for (int c = 1; c < 128; ++c)
    all += static_cast<char>(c);
  all += "\xEF\xBF\xBE\xEF\xBF\xBF";
  const std::string e = xmlEscape(all);
  const auto path = std::filesystem::temp_directory_path() /
                    ("garmcap_xml_escape_" + std::to_string(::getpid()) + ".xml");
  {
    std::ofstream f(path, std::ios::binary);
    f << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<r a=\"" << e << "\" b='" << e << "'>" << e
      << "</r>\n";
  }
  const int rc = std::system(("xmllint --noout '" + path.string() + "'").c_str());
  std::filesystem::remove(path);
  EXPECT_EQ(rc, 0) << "xmllint refused the escaped text";
}

}  // namespace
