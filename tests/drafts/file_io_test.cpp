#include "garmcap/drafts/file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace fs = std::filesystem;
using namespace garmcap::drafts;

namespace {
fs::path tempDir() {
  auto dir = fs::temp_directory_path() / ("garmcap_file_io_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}
}  // namespace

TEST(FileIo, AtomicWriteReplacesContentAndLeavesNoTemporaries) {
  const auto dir = tempDir();
  const auto file = dir / "sub" / "a.json";
  writeFileAtomic(file, "one");
  writeFileAtomic(file, "two");
  EXPECT_EQ(readFile(file), "two");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(file.parent_path()))
    ++entries;
  EXPECT_EQ(entries, 1);
  fs::remove_all(dir);
}

// A FIFO (like /dev/null or /dev/stdout, a node that is not a regular file) is written into, not
// replaced by a renamed file (run as root, `--out /dev/null` made /dev/null a plain file).
TEST(FileIo, AtomicWriteIntoAPipeKeepsThePipe) {
  const auto dir = tempDir();
  const auto fifo = dir / "pipe";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] {
    std::ifstream in(fifo, std::ios::binary);
    got.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  });
  writeFileAtomic(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_THROW(writeFileAtomic(dir, "x"), FileError);
  fs::remove(fifo);
}

TEST(FileIo, MissingFileIsNamed) {
  try {
    readFile("/nonexistent/garmcap/x.json");
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/garmcap/x.json"), std::string::npos);
  }
}

TEST(FileIo, MalformedJsonNamesFileLineAndColumn) {
  try {
    parseJson("{\n  \"a\": 1,\n  \"b\": ]\n}", "m.json");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
  }
}

TEST(FileIo, StrictFieldsNameTheField) {
  const auto j = nlohmann::json::parse(R"({"a": "x", "n": 2})");
  EXPECT_EQ(requireNumber(j, "n", "f.json"), 2.0);
  EXPECT_EQ(requireString(j, "a", "f.json"), "x");
  EXPECT_THROW(requireNumber(j, "a", "f.json"), ParseError);
  try {
    requireField(j, "missing", "f.json");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("'missing'"), std::string::npos);
  }
}

TEST(FileIo, OutOfRangeNumberIsAParseErrorNamingTheFile) {
  try {
    parseJson("{\"a\": 1e999}", "big.json");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("big.json"), std::string::npos) << e.what();
  }
}
