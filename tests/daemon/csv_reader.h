#pragma once
// A strict RFC 4180 reader for the tests that read the shop exports back (quoted fields, doubled
// quotes, line breaks inside quotes, CRLF or LF record ends), independent of the daemon's writer.
// Malformed input is a test failure (EXPECT), not an exception.
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace garmcap::test {

/// Records of `text`, fields separated by `sep` (',' or '\t'); a final empty line is dropped.
inline std::vector<std::vector<std::string>> readCsvRecords(const std::string& text,
                                                            char sep = ',') {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      EXPECT_TRUE(field.empty()) << "quote inside an unquoted field at byte " << i;
      quoted = true;
    } else if (c == sep) {
      rows.back().push_back(field);
      field.clear();
    } else if (c == '\r') {
      EXPECT_TRUE(i + 1 < text.size() && text[i + 1] == '\n') << "lone CR at byte " << i;
    } else if (c == '\n') {
      rows.back().push_back(field);
      field.clear();
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  EXPECT_FALSE(quoted) << "unterminated quote";
  if (!field.empty())
    rows.back().push_back(field);
  if (rows.back().empty())
    rows.pop_back();
  return rows;
}

}  // namespace garmcap::test
