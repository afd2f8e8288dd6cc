// The ZIP writer (zip_writer.h), read back by independent readers: Python's zipfile (every
// entry's CRC-32, names, bytes: tests/daemon/zip_read_check.py) and Info-ZIP's `unzip -t`. Plain
// archives, entries written in pieces (data descriptor), Zip64 forced on a small archive, and
// Zip64 reached by count (65,600 entries: past the 65,535 of the plain end record).
#include "garmcap/daemon/zip_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../common/run_command.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/export_zip.h"
#include "garmcap/daemon/spill_buffer.h"

namespace garmcap::daemon {
namespace {

using garmcap::testing::runCommand;

namespace fs = std::filesystem;

// Hex of bytes, as zip_read_check.py --data reports them.
std::string hex(const std::string& bytes) {
  static const char* kDigits = "0123456789abcdef";
  std::string out;
  for (unsigned char c : bytes) {
    out += kDigits[c >> 4];
    out += kDigits[c & 15];
  }
  return out;
}

class ZipWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("garmcap-zipw-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path save(const std::string& name, const std::string& bytes) {
    const auto p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  // Python's zipfile's report; fails the test when it refuses the archive.
  nlohmann::json python(const fs::path& zip, bool data) {
    int st = 0;
    const std::string out =
        runCommand("/usr/bin/python3 " GARMCAP_SOURCE_DIR "/tests/daemon/zip_read_check.py '" +
                       zip.string() + "'" + (data ? " --data" : "") + " 2>&1",
                   st);
    EXPECT_EQ(st, 0) << out;
    return st == 0 ? nlohmann::json::parse(out) : nlohmann::json::object();
  }
  // Info-ZIP's own test of every entry.
  void unzipTest(const fs::path& zip) {
    int st = 0;
    const std::string out = runCommand("unzip -tq '" + zip.string() + "' 2>&1", st);
    EXPECT_EQ(st, 0) << out;
  }
  // Whole entries, an entry in three pieces, an empty one in pieces, a binary one.
  std::string mixed(ZipWriter& z) {
    std::string out = z.file("a.txt", "hello");
    out += z.begin("dir/streamed.csv");
    for (const std::string piece : {"h1,h2\r\n", "1,2\r\n", "3,4\r\n"}) {
      z.add(piece);
      out += piece;
    }
    out += z.end();
    out += z.begin("empty-streamed");
    out += z.end();
    out += z.file("images/Été.bin", kBinary);
    for (std::string piece; !(piece = z.tail(7)).empty();)
      out += piece;
    return out;
  }
  void expectMixed(const nlohmann::json& r) {
    EXPECT_EQ(r["names"], nlohmann::json::array(
                              {"a.txt", "dir/streamed.csv", "empty-streamed", "images/Été.bin"}));
    EXPECT_EQ(r["data"]["a.txt"], hex("hello"));
    EXPECT_EQ(r["data"]["dir/streamed.csv"], hex("h1,h2\r\n1,2\r\n3,4\r\n"));
    EXPECT_EQ(r["data"]["empty-streamed"], "");
    EXPECT_EQ(r["data"]["images/Été.bin"], hex(kBinary));
  }
  const std::string kBinary{"\x00\xff\x89PNG\r\n", 8};
  fs::path dir_;
};

TEST_F(ZipWriterTest, PlainArchiveWithEntriesInPiecesReadsBack) {
  ZipWriter z;
  const std::string bytes = mixed(z);
  EXPECT_EQ(z.bytesWritten(), bytes.size());
  EXPECT_EQ(z.entries(), 4u);
  const auto p = save("plain.zip", bytes);
  const auto r = python(p, true);
  expectMixed(r);
  EXPECT_FALSE(r["zip64"].get<bool>());
  unzipTest(p);
}

TEST_F(ZipWriterTest, ForcedZip64ArchiveReadsBack) {
  ZipWriter z(ZipWriter::Options{true});
  const std::string bytes = mixed(z);
  const auto p = save("forced.zip", bytes);
  const auto r = python(p, true);
  expectMixed(r);
  EXPECT_TRUE(r["zip64"].get<bool>());
  // The plain end record says 0xFFFF entries: a reader must have taken the zip64 record.
  EXPECT_EQ(static_cast<unsigned char>(bytes[bytes.size() - 22 + 8]), 0xff);
  unzipTest(p);
}

TEST_F(ZipWriterTest, MoreThan65535EntriesTakeZip64) {
  ZipWriter z;
  std::string bytes;
  const int n = 65600;
  for (int i = 0; i < n; ++i)
    bytes += z.file("f/" + std::to_string(i) + ".txt", std::to_string(i * 7));
  bytes += z.begin("last.csv");
  z.add("x\n");
  bytes += "x\n";
  bytes += z.end();
  for (std::string piece; !(piece = z.tail(64 * 1024)).empty();)
    bytes += piece;
  const auto p = save("many.zip", bytes);
  const auto r = python(p, false);
  EXPECT_EQ(r["count"], n + 1);
  EXPECT_TRUE(r["zip64"].get<bool>());
  EXPECT_EQ(r["names"][n - 1], "f/" + std::to_string(n - 1) + ".txt");
  EXPECT_EQ(r["names"][n], "last.csv");
  unzipTest(p);
  // Python reads a file from the far end of the archive back right.
  int st = 0;
  const std::string out = runCommand(
      "/usr/bin/python3 -c 'import sys, zipfile; "
      "print(zipfile.ZipFile(sys.argv[1]).read(\"f/65599.txt\").decode())' '" +
          p.string() + "' 2>&1",
      st);
  EXPECT_EQ(out, std::to_string(65599 * 7) + "\n");
}

TEST_F(ZipWriterTest, StoreZipIsTheWritersWholeEntries) {
  ZipWriter z;
  std::string bytes = z.file("x/a", "1");
  bytes += z.file("b", "22");
  for (std::string piece; !(piece = z.tail(3)).empty();)
    bytes += piece;
  EXPECT_EQ(storeZip({{"x/a", "1"}, {"b", "22"}}), bytes);
  EXPECT_THROW(z.file("c", "3"), std::logic_error);  // after the end
}

TEST_F(ZipWriterTest, RefusesBadPathsAndMisuse) {
  ZipWriter z;
  EXPECT_THROW(z.file("../x", "a"), ExportError);
  EXPECT_THROW(z.begin("/abs"), ExportError);
  EXPECT_THROW(z.add("x"), std::logic_error);
  EXPECT_THROW(z.end(), std::logic_error);
  z.begin("ok");
  EXPECT_THROW(z.file("other", "a"), std::logic_error);
  EXPECT_THROW(z.tail(10), std::logic_error);
}

TEST(ZipCrc32, MatchesTheKnownCheckValue) {
  // The CRC-32 check value of "123456789" (IEEE 802.3), whole and continued in two parts.
  EXPECT_EQ(zipCrc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(zipCrc32("6789", zipCrc32("12345")), 0xCBF43926u);
}

TEST(SpillBuffer, ReadsBackWhatWasAppendedPastItsMemoryLimit) {
  for (const std::size_t limit : {std::size_t{0}, std::size_t{10}, std::size_t{1} << 20}) {
    SpillBuffer b(limit);
    std::string all;
    for (int i = 0; i < 1000; ++i) {
      const std::string s = "line " + std::to_string(i) + "\n";
      b.append(s);
      all += s;
    }
    EXPECT_EQ(b.size(), all.size());
    std::string back;
    for (std::string part; !(part = b.read(333)).empty();)
      back += part;
    EXPECT_EQ(back, all) << "limit " << limit;
    EXPECT_THROW(b.append("more"), std::logic_error);
  }
}

}  // namespace
}  // namespace garmcap::daemon
