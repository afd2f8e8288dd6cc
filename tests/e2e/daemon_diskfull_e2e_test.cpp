// Issue 16: the station's disk fills up (a small tmpfs as its data folder). Jobs end failed with
// the reason instead of staying queued or running, writes answer 507 naming the cause, reads and
// what is already stored keep working, and once space is freed captures work again.

#include <gtest/gtest.h>
#include <sys/mount.h>

#include "daemon_harness.h"

namespace garmcap::e2e {
namespace {

// A tmpfs of `mb` at `dir`, unmounted on destruction; skipped where mounting is not allowed.
class SmallDisk {
 public:
  SmallDisk(const std::filesystem::path& dir, int mb) : dir_(dir) {
    std::filesystem::create_directories(dir);
    const std::string opts = "size=" + std::to_string(mb) + "m";
    mounted_ = ::mount("tmpfs", dir.c_str(), "tmpfs", 0, opts.c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_)
      ::umount2(dir_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  /// Fills the disk with one file; returns its path.
  std::filesystem::path fill() const {
    const auto f = dir_ / "filler.bin";
    std::FILE* out = std::fopen(f.c_str(), "wb");
    std::vector<char> block(64 * 1024, 'x');
    while (out && std::fwrite(block.data(), 1, block.size(), out) == block.size()) {
    }
    if (out)
      std::fclose(out);
    return f;
  }

 private:
  std::filesystem::path dir_;
  bool mounted_ = false;
};

TEST(DiskFull, JobsFailWithTheReasonWritesAre507AndNothingStoredIsLost) {
  TempDir dir;
  SmallDisk disk(dir.path() / "data", 24);
  if (!disk.mounted())
    GTEST_SKIP() << "cannot mount a tmpfs here (needs CAP_SYS_ADMIN)";
  Daemon d(dir.path() / "data", {}, makeSimulatedRig(dir.path()));
  ASSERT_EQ(d.waitJob(d.post("/api/button").json()["job"])["state"], "done");
  auto first = d.waitJob(d.post("/api/capture", R"({"sku": "DISK-1"})").json()["job"]);
  ASSERT_EQ(first["state"], "done") << first.dump();
  const std::string item = "/api/items/" + std::to_string(first["item_id"].get<std::int64_t>());
  const std::string before = d.get(item).body;

  const auto filler = disk.fill();
  // A capture on the full disk ends failed, with the disk named, within a bounded time.
  auto r = d.post("/api/capture", R"({"sku": "DISK-2"})");
  if (r.status == 202) {
    auto job = d.waitJob(r.json()["job"], 60s);
    EXPECT_EQ(job["state"], "failed") << job.dump();
    EXPECT_NE(job.value("error", "").find("disk"), std::string::npos) << job.dump();
  } else {
    EXPECT_EQ(r.status, 507) << r.body;
    EXPECT_NE(r.json().value("error", "").find("disk"), std::string::npos) << r.body;
  }
  // Writes answer (507, naming the disk), never hang, never 400.
  auto patch = httpCall(d.port(), http::verb::patch, item, R"({"title": "Full disk"})");
  EXPECT_EQ(patch.status, 507) << patch.body;
  EXPECT_NE(patch.json().value("error", "").find("disk"), std::string::npos) << patch.body;
  EXPECT_EQ(patch.body.find("INSERT"), std::string::npos);
  EXPECT_EQ(patch.body.find("UPDATE"), std::string::npos);
  auto del = httpCall(d.port(), http::verb::delete_, item);
  EXPECT_EQ(del.status, 507) << del.body;
  // Reads work, and what was stored is as it was.
  EXPECT_EQ(d.get(item).body, before);
  EXPECT_EQ(d.get("/api/status").status, 200);

  // Space back: the station captures again without a restart.
  std::filesystem::remove(filler);
  auto again = d.waitJob(d.post("/api/capture", R"({"sku": "DISK-3"})").json()["job"]);
  EXPECT_EQ(again["state"], "done") << again.dump();
  EXPECT_EQ(d.get("/api/items").json()["total"], 2);
  EXPECT_EQ(d.terminate(), 0);
}

// garmcapd started on a full disk comes up read-only: the catalog and photos can be browsed and
// exported, /api/status says why nothing can be captured, and writes are 507.
TEST(DiskFull, StartOnAFullDiskIsReadOnlyAndSaysSo) {
  TempDir dir;
  SmallDisk disk(dir.path() / "data", 24);
  if (!disk.mounted())
    GTEST_SKIP() << "cannot mount a tmpfs here (needs CAP_SYS_ADMIN)";
  const auto rig = makeSimulatedRig(dir.path());
  std::string item, before;
  {
    Daemon d(dir.path() / "data", {}, rig);
    ASSERT_EQ(d.waitJob(d.post("/api/button").json()["job"])["state"], "done");
    auto job = d.waitJob(d.post("/api/capture", R"({"sku": "RO-1"})").json()["job"]);
    ASSERT_EQ(job["state"], "done") << job.dump();
    item = "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>());
    before = d.get(item).body;
    ASSERT_EQ(d.terminate(), 0);
  }
  disk.fill();
  Daemon d(dir.path() / "data", {}, rig);
  auto status = d.get("/api/status");
  ASSERT_EQ(status.status, 200) << status.body;
  EXPECT_EQ(status.json().value("read_only", false), true) << status.body;
  EXPECT_NE(status.json().value("last_error", "").find("disk"), std::string::npos) << status.body;
  EXPECT_EQ(d.get(item).body, before);
  EXPECT_EQ(d.get(item + "/pattern.json").status, 200);
  auto r = d.post("/api/capture", R"({"sku": "RO-2"})");
  EXPECT_EQ(r.status, 507) << r.body;
  EXPECT_EQ(d.terminate(), 0);
}

}  // namespace
}  // namespace garmcap::e2e
