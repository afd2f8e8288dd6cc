#include "garmcap/daemon/toml_input.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "garmcap/daemon/config.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

std::string repeat(const std::string& s, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i)
    out += s;
  return out;
}

std::string errorOf(const std::string& text) {
  try {
    (void)parseTomlText(text, "t.toml");
  } catch (const TomlInputError& e) {
    return e.what();
  }
  return "";
}

// The three inputs tests/fuzz/fuzz_config_toml found in toml11 3.7.1, as a station's admin
// could write them: each must be a clear error naming its line, never a crash or a hang.
TEST(TomlInput, NestingPastTheLimitIsRefusedWithItsLine) {
  // 200,000 '[' overflowed the stack of the release garmcapd (SIGSEGV at start).
  EXPECT_EQ(errorOf("# a comment\nm = " + repeat("[", 200000)),
            "line 2: arrays, inline tables or table headers nested deeper than 32");
  EXPECT_NE(errorOf("m = " + repeat("{a=", 200000) + "1" + repeat("}", 200000)).find("line 1: "),
            std::string::npos);
  // At the limit it still parses, to the value written.
  const auto at = parseTomlText("m = " + repeat("[", 32) + "7" + repeat("]", 32) + "\n", "t");
  const toml::value* v = &toml::find(at, "m");
  for (int i = 0; i < 32; ++i)
    v = &v->as_array().at(0);
  EXPECT_EQ(v->as_integer(), 7);
}

TEST(TomlInput, LongBinaryIntegersAreRefused) {
  // 64 digits: a signed overflow inside toml11's parse_binary_integer (UBSan).
  EXPECT_EQ(errorOf("2=0b" + repeat("0", 60) + "111_0\n"),
            "line 1: a binary integer of 64 digits (at most 62)");
  EXPECT_EQ(toml::find<std::int64_t>(parseTomlText("b = 0b" + repeat("1", 62) + "\n", "t"), "b"),
            (std::int64_t{1} << 62) - 1);
}

TEST(TomlInput, KeysOfTooManyPartsAreRefused) {
  // 200,000 parts took toml11 over 20 s (quadratic); 20,000 took 2-3 s.
  EXPECT_EQ(errorOf("\n\na" + repeat(".a", 200000) + " = 1\n"),
            "line 3: a dotted key or table header of more than 32 parts");
  EXPECT_NE(errorOf("[" + repeat("a.", 40) + "a]\n").find("more than 32 parts"), std::string::npos);
  const auto ok = parseTomlText("a" + repeat(".a", 31) + " = 1\n", "t");
  EXPECT_TRUE(ok.is_table());
}

TEST(TomlInput, StringsCommentsAndValuesAreNotCounted) {
  // Brackets, dots and binary-looking digits inside strings and comments, floats, dates and
  // many values in one array are ordinary TOML and must pass the checks.
  const std::string text = "# [[[[ " + repeat("[", 40) + " 0b" + repeat("1", 80) + "\n" + "s = \"" +
                           repeat("[.", 40) + "\\\" 0b" + repeat("1", 80) + "\"\n" + "l = '" +
                           repeat("{.", 40) + "'\n" + "m = \"\"\"\n" + repeat("[.", 40) +
                           "\n\"\"\"\n" + "n = '''" + repeat("{.", 40) + "'''\n" + "f = [" +
                           repeat("1.5, ", 100) + "2.5]\n" + "d = 1979-05-27T07:32:00.999Z\n" +
                           "[a.\"b.c.d.e\".f]\nx = 0b101\n";
  const auto doc = parseTomlText(text, "t");
  EXPECT_EQ(toml::find<std::string>(doc, "s").size(), 80u + 1u + 3u + 80u);
  EXPECT_EQ(toml::find(doc, "f").as_array().size(), 101u);
  EXPECT_EQ(toml::find<std::int64_t>(doc, "a", "b.c.d.e", "f", "x"), 5);
}

// Up to two quotes of a multi-line string's content may stand before its closing three. Closing
// at the first three hid the brackets after a stray quote (fuzz_config_toml: a stack overflow).
TEST(TomlInput, MultiLineStringsEndAtTheirLastThreeQuotes) {
  const auto doc = parseTomlText("a = '''x''''\nb = \"\"\"y\"\"\"\"\"\nc = ''''''\n", "t");
  EXPECT_EQ(toml::find<std::string>(doc, "a"), "x'");
  EXPECT_EQ(toml::find<std::string>(doc, "b"), "y\"\"");
  EXPECT_EQ(toml::find<std::string>(doc, "c"), "");
  EXPECT_EQ(errorOf("m = [['''x'''', " + repeat("[", 40)),
            "line 1: arrays, inline tables or table headers nested deeper than 32");
  EXPECT_EQ(errorOf("m = [[\"\"\"x\"\"\"\", " + repeat("[", 40)),
            "line 1: arrays, inline tables or table headers nested deeper than 32");
}

TEST(TomlInput, InvalidUtf8AndSyntaxErrorsAreRefused) {
  EXPECT_EQ(errorOf("a = '\xff'\n"), "not valid UTF-8 (TOML files are UTF-8)");
  EXPECT_NE(errorOf("[http\n").find("t.toml"), std::string::npos);
}

// Through the station's own reader: the error names the file and the line.
TEST(TomlInput, TheStationsConfigNamesFileAndLine) {
  test::TempDir dir;
  const auto p = dir.path() / "garmcapd.toml";
  std::ofstream(p) << "[http]\nx = " << repeat("[", 100000) << "\n";
  try {
    (void)loadConfig(p);
    FAIL() << "a config nested 100,000 deep was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() +
                                         ": line 2: arrays, inline tables or table "
                                         "headers nested deeper than 32");
  }
}

}  // namespace
}  // namespace garmcap::daemon
