// End-to-end tests of what happens around a capture rather than in it, against the real garmcapd
// process on a case of the bundled simulator rig (so captures calibrate and file items):
//   - SIGKILL (a crash or a power cut) at random moments while item-creating captures run,
//   - SIGTERM (finish the job in hand, keep the queue for the next start),
//   - SIGHUP (reload; an invalid file keeps the running config and the log names key and reason;
//     a new size chart grades the next capture),
//   - the systemd notify protocol (READY, RELOADING, STOPPING, WATCHDOG pings) on a socket the
//     test binds as NOTIFY_SOCKET.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>

#include <cstdio>
#include <map>
#include <random>
#include <sstream>

#include "daemon_harness.h"

namespace garmcap::e2e {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string readAll(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// sha256 of files, by coreutils' sha256sum: an implementation independent of the daemon's.
std::map<std::string, std::string> sha256Files(const std::vector<std::filesystem::path>& files) {
  std::map<std::string, std::string> out;
  if (files.empty())
    return out;
  std::string cmd = "sha256sum";
  for (const auto& f : files)
    cmd += " '" + f.string() + "'";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p)
    return out;
  char line[4096];
  while (std::fgets(line, sizeof line, p)) {
    std::string l(line);
    if (l.size() > 66 && l[64] == ' ') {
      std::string name = l.substr(66);
      while (!name.empty() && name.back() == '\n')
        name.pop_back();
      out[name] = l.substr(0, 64);
    }
  }
  pclose(p);
  return out;
}

std::filesystem::path blobPath(const std::filesystem::path& data, const std::string& sha) {
  return data / "blobs" / sha.substr(0, 2) / sha;
}

std::int64_t count(const std::filesystem::path& db, const std::string& sql) {
  auto c = column(db, sql.c_str());
  return c.empty() ? -1 : std::stoll(c[0]);
}

// --- SIGKILL ----------------------------------------------------------------------------------

// What the API told a client: a job it accepted, its last reported state, and for done jobs
// the item as served.
struct Seen {
  std::string state = "queued";
  std::string stage;
  Json item;  // set once the job was reported done
};

TEST(DaemonResilience, SigkillWhileCapturesFileItemsLosesNothingReported) {
  const auto t0 = Clock::now();
  TempDir dir;
  const auto data = dir.path() / "data";
  const auto db = data / "catalog.sqlite";
  const auto rig = makeSimulatedRig(dir.path());
  std::map<std::int64_t, Seen> jobs;

  // Poll every accepted job once; fetch the item of each newly done one.
  auto poll = [&](const Daemon& d) {
    for (auto& [id, seen] : jobs) {
      if (seen.state == "done" || seen.state == "failed")
        continue;
      auto j = d.get("/api/jobs/" + std::to_string(id)).json();
      if (!j.is_object() || !j.contains("state"))
        continue;
      seen.state = j["state"];
      seen.stage = j.value("stage", "");
      if (seen.state == "done" && j["item_id"].is_number())
        seen.item = d.get("/api/items/" + j["item_id"].dump()).json();
    }
  };

  // Round 0: calibrate; then time one undisturbed capture in a fresh process, from the moment
  // it serves (a new process loads the form model on its first capture, as every round will).
  {
    Daemon d(data, DaemonOptions{{}, rig, {}, {}});
    ASSERT_EQ(d.waitJob(d.post("/api/capture/empty").json()["job"])["state"], "done");
    ASSERT_EQ(d.terminate(), 0);
  }
  double captureS = 0;
  {
    Daemon d(data, DaemonOptions{{}, rig, {}, {}});
    const auto c0 = Clock::now();
    const std::int64_t id = d.post("/api/capture").json()["job"];
    jobs[id] = {};
    ASSERT_EQ(d.waitJob(id)["state"], "done");
    captureS = secondsSince(c0);
    poll(d);
    d.kill9();
  }

  // Rounds: keep two captures in hand (one running, one queued) and kill at a moment when
  // the daemon is making an item. Seeded from the clock, printed for a re-run.
  const unsigned seed = static_cast<unsigned>(std::random_device{}());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(0, 1);
  // Twenty kills, as the issue's acceptance asks; the time guard only keeps a badly loaded
  // machine from running into ctest's timeout (the rounds done are checked below).
  const int kRounds = 20;
  std::map<std::string, int> killedIn;  // stage of the running job at the kill
  std::set<std::int64_t> queuedAtKill;
  auto doneCount = [&] {
    return std::count_if(jobs.begin(), jobs.end(),
                         [](const auto& j) { return j.second.state == "done"; });
  };
  for (int round = 0; round < kRounds && secondsSince(t0) < 240; ++round) {
    Daemon d(data, DaemonOptions{{}, rig, {}, {}});
    const auto started = Clock::now();  // a resumed job starts with the process
    auto status = d.get("/api/status").json();
    int inHand = status["queue"].get<int>() + (status["job"].is_null() ? 0 : 1);
    for (; inHand < 2; ++inHand) {
      auto r = round % 2 ? d.post("/api/button") : d.post("/api/capture");
      ASSERT_EQ(r.status, 202) << r.body;
      jobs[r.json()["job"].get<std::int64_t>()] = {};
    }
    // Odd rounds: 0..150 ms after a job starts writing its images, a short window that random
    // moments seldom hit. Even rounds: the first job is filed (and reported: one more item to
    // check), then a random moment over the second one's duration. Both bounded, for a slow
    // machine.
    const auto doneBefore = doneCount();
    auto killAt = started + std::chrono::duration<double>(3 * captureS + 1);
    bool armed = true;
    while (Clock::now() < killAt) {
      poll(d);
      const bool trigger =
          round % 2 ? std::any_of(jobs.begin(), jobs.end(),
                                  [](const auto& j) {
                                    return j.second.state == "running" && j.second.stage == "store";
                                  })
                    : doneCount() > doneBefore;
      if (armed && trigger) {
        armed = false;
        // The load on a shared machine varies: keep the estimate of a capture honest.
        if (round % 2)
          captureS = std::max(captureS, secondsSince(started) + 0.3);
        const double wait = round % 2 ? 0.15 * jitter(rng) : 0.9 * captureS * jitter(rng);
        killAt = Clock::now() + std::chrono::duration<double>(wait);
      }
      std::this_thread::sleep_for(5ms);
    }
    const double delayS = secondsSince(started);
    d.kill9();
    std::string stage = "idle";
    for (const auto& [id, seen] : jobs) {
      if (seen.state == "running")
        stage = seen.stage;
      if (seen.state == "queued")
        queuedAtKill.insert(id);
    }
    ++killedIn[stage];
    if (getenv("GARMCAP_E2E_VERBOSE"))
      std::printf("[crash] round %d: kill at %.2f s in %s\n", round, delayS, stage.c_str());
    ASSERT_EQ(integrity(db), "ok") << "after kill " << round << " (seed " << seed << ")";
  }

  // A last start: resumed jobs run to the end, then every check.
  {
    Daemon d(data, DaemonOptions{{}, rig, {}, {}});
    const auto deadline = Clock::now() + 60s;
    while (Clock::now() < deadline) {
      auto s = d.get("/api/status").json();
      if (s["queue"] == 0 && s["job"].is_null())
        break;
      std::this_thread::sleep_for(50ms);
    }
    poll(d);
    // Every item the API reported is served as it was, images byte for byte.
    for (const auto& [id, seen] : jobs) {
      if (seen.item.is_null())
        continue;
      const std::string itemUrl = "/api/items/" + seen.item["id"].dump();
      auto now = d.get(itemUrl);
      ASSERT_EQ(now.status, 200) << "item of job " << id << " is gone";
      EXPECT_EQ(now.json()["measurements"], seen.item["measurements"]);
      EXPECT_EQ(now.json()["images"], seen.item["images"]);
      EXPECT_EQ(d.get(itemUrl + "/pattern.json").status, 200);
      for (const auto& [kind, im] : seen.item["images"].items()) {
        const std::string sha = im["sha256"];
        const auto file = blobPath(data, sha);
        ASSERT_TRUE(std::filesystem::exists(file)) << kind << " of job " << id;
        EXPECT_EQ(sha256Files({file})[file.string()], sha) << kind << " of job " << id;
        EXPECT_EQ(d.get(im["url"].get<std::string>()).status, 200) << kind;
      }
    }
    EXPECT_EQ(d.terminate(), 0);
  }
  EXPECT_EQ(integrity(db), "ok");

  // No job lost: each accepted job ended done, or failed because it was interrupted while
  // running. A job queued at a kill was taken up at the next start (done, or interrupted in a
  // later round), never dropped, cancelled or expired.
  int done = 0, interrupted = 0;
  for (const auto& [id, seen] : jobs) {
    const auto state = column(
        db, ("SELECT state || '|' || error FROM jobs WHERE id = " + std::to_string(id)).c_str());
    ASSERT_EQ(state.size(), 1u) << "job " << id << " is not in the catalog";
    if (state[0] == "done|") {
      ++done;
      continue;
    }
    EXPECT_EQ(state[0].rfind("failed|interrupted", 0), 0u) << "job " << id << ": " << state[0];
    ++interrupted;
    EXPECT_NE(seen.state, "done") << "job " << id << " was reported done, is now " << state[0];
  }
  int resumedDone = 0;  // presses queued at a kill that the next start carried through
  for (auto id : queuedAtKill)
    resumedDone += jobs[id].state == "done";

  // No half item: each has its job done, its frames, measurements and a pattern.
  EXPECT_EQ(count(db,
                  "SELECT count(*) FROM items i LEFT JOIN jobs j ON j.id = i.job_id "
                  "WHERE j.state IS NOT 'done' "
                  "OR (SELECT count(*) FROM item_images ii WHERE ii.item_id = i.id "
                  "    AND ii.kind IN ('dressed', 'empty')) != 2 "
                  "OR NOT EXISTS (SELECT 1 FROM measurements m WHERE m.item_id = i.id) "
                  "OR NOT EXISTS (SELECT 1 FROM patterns p WHERE p.item_id = i.id)"),
            0);
  EXPECT_EQ(count(db, "SELECT count(*) FROM items"), done);
  // Files and rows one to one, every file's content matching its name, no temp file left.
  const auto rows = column(db, "SELECT sha256 FROM images");
  const std::set<std::string> rowSet(rows.begin(), rows.end());
  EXPECT_EQ(blobsOnDisk(data), rowSet);
  std::vector<std::filesystem::path> files;
  for (const auto& sha : rowSet)
    files.push_back(blobPath(data, sha));
  const auto sums = sha256Files(files);
  for (const auto& f : files)
    EXPECT_EQ(sums.count(f.string()) ? sums.at(f.string()) : "missing", f.filename().string());
  EXPECT_TRUE(std::filesystem::is_empty(data / "blobs" / "tmp"));

  std::string stages;
  for (const auto& [stage, n] : killedIn)
    stages += " " + stage + "=" + std::to_string(n);
  std::printf(
      "[crash] seed %u, capture %.2f s, kills in:%s; %zu jobs: %d done, %d interrupted; "
      "%zu queued at a kill, %d of them resumed to done; %zu blobs; %.1f s\n",
      seed, captureS, stages.c_str(), jobs.size(), done, interrupted, queuedAtKill.size(),
      resumedDone, rowSet.size(), secondsSince(t0));
  EXPECT_GE(done, 2);
  int kills = 0;
  for (const auto& [stage, n] : killedIn)
    kills += n;
  EXPECT_GE(kills, 10) << "the time guard stopped the loop early (machine overloaded?)";
  // The point of the test: some kills hit a capture past its still, while it makes an item.
  int inProcessing = 0;
  for (const auto& [stage, n] : killedIn)
    if (stage != "idle" && stage != "capturing" && stage != "queued")
      inProcessing += n;
  EXPECT_GE(inProcessing, 1) << "no kill landed while an item was being made (seed " << seed << ")";
}

// --- SIGTERM ----------------------------------------------------------------------------------

TEST(DaemonResilience, SigtermFinishesTheJobInHandAndKeepsTheQueue) {
  TempDir dir;
  const auto data = dir.path() / "data";
  const auto rig = makeSimulatedRig(dir.path());
  std::int64_t running = 0, queued = 0;
  {
    Daemon d(data, DaemonOptions{{}, rig, {}, {}});
    ASSERT_EQ(d.waitJob(d.post("/api/button").json()["job"])["state"], "done");  // bare form
    running = d.post("/api/capture", R"({"sku": "TERM-1"})").json()["job"];
    queued = d.post("/api/button").json()["job"];
    // SIGTERM while the first capture is past its still, in the pipeline.
    const auto deadline = Clock::now() + 30s;
    while (Clock::now() < deadline) {
      auto j = d.get("/api/jobs/" + std::to_string(running)).json();
      if (j["state"] == "running" && j["stage"] != "capturing")
        break;
      std::this_thread::sleep_for(10ms);
    }
    d.signal(SIGTERM);
    // The listener closes at once; the process stays until the job is filed.
    EXPECT_EQ(d.wait(60s), 0);
  }
  const auto db = data / "catalog.sqlite";
  EXPECT_EQ(integrity(db), "ok");
  EXPECT_EQ(column(db, ("SELECT state FROM jobs WHERE id = " + std::to_string(running)).c_str()),
            std::vector<std::string>{"done"});
  EXPECT_EQ(column(db, "SELECT sku FROM items"), std::vector<std::string>{"TERM-1"});
  EXPECT_EQ(column(db, ("SELECT state FROM jobs WHERE id = " + std::to_string(queued)).c_str()),
            std::vector<std::string>{"queued"});
  // The next start runs the press that was waiting.
  Daemon d(data, DaemonOptions{{}, rig, {}, {}});
  auto j = d.waitJob(queued);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(d.get("/api/items").json()["total"], 2);
  EXPECT_EQ(d.terminate(), 0);
}

// --- MemoryDenyWriteExecute --------------------------------------------------------------------

TEST(DaemonResilience, CapturesUnderMemoryDenyWriteExecute) {
  // Does this kernel enforce it? A child sets it and tries a writable, executable mapping.
  const pid_t probe = fork();
  if (probe == 0) {
    if (!denyWriteExecute())
      _exit(2);
    void* p =
        mmap(nullptr, 4096, PROT_READ | PROT_WRITE | PROT_EXEC, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    _exit(p == MAP_FAILED ? 0 : 1);
  }
  int st = 0;
  waitpid(probe, &st, 0);
  if (WIFEXITED(st) && WEXITSTATUS(st) == 2)
    GTEST_SKIP() << "the kernel has no PR_SET_MDWE (Linux >= 6.3)";
  ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "W+X mapping allowed under MDWE";

  // Calibration, GarmCap, grading, PNG encoding and the HTTP server with W+X memory refused.
  TempDir dir;
  const auto rig = makeSimulatedRig(dir.path());
  DaemonOptions o{{}, rig, {}, {}};
  o.denyWriteExecute = true;
  Daemon d(dir.path() / "data", o);
  ASSERT_EQ(d.waitJob(d.post("/api/capture/empty").json()["job"])["state"], "done");
  auto job = d.waitJob(d.post("/api/capture").json()["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  auto item = d.get("/api/items/" + job["item_id"].dump()).json();
  EXPECT_TRUE(item["images"].contains("product")) << item.dump();
  EXPECT_EQ(d.get("/api/items/" + job["item_id"].dump() + "/sizeguide.csv").status, 200);
  EXPECT_EQ(d.terminate(), 0);
}

// --- systemd notify socket ----------------------------------------------------------------------

// A datagram socket bound where the daemon's NOTIFY_SOCKET points, as systemd would.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
      throw std::runtime_error("cannot bind " + path.string());
  }
  ~NotifySocket() {
    ::close(fd_);
    std::filesystem::remove(path_);
  }
  struct Message {
    double at = 0;  // s since the socket was made
    std::string text;
  };
  /// Reads messages until `until` holds for the messages so far or `limit` passes.
  template <typename Pred>
  const std::vector<Message>& collect(std::chrono::milliseconds limit, Pred until) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline && !until(messages_)) {
      char buf[4096];
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n > 0)
        messages_.push_back({secondsSince(made_), std::string(buf, static_cast<std::size_t>(n))});
      else
        std::this_thread::sleep_for(5ms);
    }
    return messages_;
  }
  const std::vector<Message>& collect(std::chrono::milliseconds limit) {
    return collect(limit, [](const auto&) { return false; });
  }
  static bool has(const std::vector<Message>& ms, const std::string& what) {
    return std::any_of(ms.begin(), ms.end(),
                       [&](const Message& m) { return m.text.find(what) != std::string::npos; });
  }
  const std::string& path() const { return path_; }
  Clock::time_point made() const { return made_; }

 private:
  std::string path_;
  int fd_ = -1;
  Clock::time_point made_ = Clock::now();
  std::vector<Message> messages_;
};

TEST(DaemonResilience, WatchdogPingsAtHalfTheIntervalWhileHealthy) {
  TempDir dir;
  NotifySocket sock(dir.path() / "notify.sock");
  const int kWatchdogUs = 400000;  // pings expected every 200 ms
  Daemon d(dir.path() / "data", DaemonOptions{{},
                                              {},
                                              {{"NOTIFY_SOCKET", sock.path()},
                                               {"WATCHDOG_USEC", std::to_string(kWatchdogUs)}},
                                              {}});
  auto& ms = sock.collect(5s, [](const auto& m) { return NotifySocket::has(m, "READY=1"); });
  ASSERT_TRUE(NotifySocket::has(ms, "READY=1"));
  // The first ping goes out with the start-up; then one per half interval.
  sock.collect(2000ms);
  std::vector<double> pings;
  for (const auto& m : ms)
    if (m.text.find("WATCHDOG=1") != std::string::npos)
      pings.push_back(m.at);
  ASSERT_GE(pings.size(), 6u) << "pings in 2 s at 200 ms intervals";
  double maxGap = 0;
  for (std::size_t i = 1; i < pings.size(); ++i)
    maxGap = std::max(maxGap, pings[i] - pings[i - 1]);
  std::printf("[watchdog] %zu pings, max gap %.0f ms (WATCHDOG_USEC %d)\n", pings.size(),
              maxGap * 1000, kWatchdogUs);
  EXPECT_LT(maxGap, kWatchdogUs / 1e6) << "systemd would have restarted the daemon";
  EXPECT_TRUE(NotifySocket::has(ms, "STATUS=uncalibrated"));
  // The stop is announced before the exit.
  EXPECT_EQ(d.terminate(), 0);
  EXPECT_TRUE(NotifySocket::has(
      sock.collect(1000ms, [](const auto& m) { return NotifySocket::has(m, "STOPPING=1"); }),
      "STOPPING=1"));
}

/// Times of the WATCHDOG=1 pings among `ms`.
std::vector<double> pingTimes(const std::vector<NotifySocket::Message>& ms) {
  std::vector<double> out;
  for (const auto& m : ms)
    if (m.text.find("WATCHDOG=1") != std::string::npos)
      out.push_back(m.at);
  return out;
}

/// The longest gap between consecutive pings that ends in [from, to], and where it starts.
std::pair<double, double> longestGapEndingIn(const std::vector<double>& pings, double from,
                                             double to) {
  double gap = 0, start = 0;
  for (std::size_t i = 1; i < pings.size(); ++i)
    if (pings[i] >= from && pings[i] <= to && pings[i] - pings[i - 1] > gap)
      gap = pings[i] - pings[i - 1], start = pings[i - 1];
  return {gap, start};
}

// A blocked event loop sends no pings: systemd (WatchdogSec) would kill and restart the daemon.
// The loop is blocked through the test-only hook POST /api/sim/stall (GARMCAP_TEST_HOOKS).
TEST(DaemonResilience, WatchdogPingsStopWhileTheEventLoopIsBlocked) {
  TempDir dir;
  NotifySocket sock(dir.path() / "notify.sock");
  const int kWatchdogUs = 400000;  // pings every 200 ms
  const int kStallMs = 2000;
  Daemon d(dir.path() / "data", DaemonOptions{{},
                                              {},
                                              {{"NOTIFY_SOCKET", sock.path()},
                                               {"WATCHDOG_USEC", std::to_string(kWatchdogUs)}},
                                              {}});
  ASSERT_TRUE(NotifySocket::has(
      sock.collect(5s, [](const auto& m) { return NotifySocket::has(m, "READY=1"); }), "READY=1"));
  if (d.post("/api/sim/stall", R"({"ms": 0})").status == 404)
    GTEST_SKIP() << "garmcapd built without GARMCAP_TEST_HOOKS";
  sock.collect(1000ms);
  // The stalling request answers only when the loop runs again: send it from a thread.
  const double stallSent = secondsSince(sock.made());
  Reply stalled;
  std::thread client(
      [&] { stalled = d.post("/api/sim/stall", R"({"ms": )" + std::to_string(kStallMs) + "}"); });
  sock.collect(std::chrono::milliseconds(kStallMs + 1500));
  client.join();
  ASSERT_EQ(stalled.status, 200) << stalled.body;
  const auto pings = pingTimes(sock.collect(0ms));
  // Before the stall: a ping every half interval.
  EXPECT_LT(longestGapEndingIn(pings, 0.3, stallSent).first, kWatchdogUs / 1e6);
  // During it none: the gap spans the stall and is longer than WatchdogSec.
  const auto [gap, gapStart] = longestGapEndingIn(pings, stallSent, 1e9);
  std::printf("[watchdog] loop blocked %d ms: no ping for %.0f ms (WATCHDOG_USEC %d)\n", kStallMs,
              gap * 1000, kWatchdogUs);
  EXPECT_GE(gap, kStallMs / 1000.0 - 0.25) << "pings went on while the loop was blocked";
  EXPECT_GT(gap, kWatchdogUs / 1e6) << "systemd would not have noticed";
  EXPECT_GE(gapStart, stallSent - 0.25);
  // After it the pings resume at the half interval.
  const double resumed = gapStart + gap;
  EXPECT_GE(std::count_if(pings.begin(), pings.end(),
                          [&](double t) { return t > resumed && t < resumed + 1.0; }),
            3);
  EXPECT_EQ(d.get("/api/status").status, 200);
  EXPECT_EQ(d.terminate(), 0);
}

// The loop runs and the API answers, but a still that does not come back is a hung camera: the
// pings are withheld (so systemd restarts the service) and resume when the camera answers.
TEST(DaemonResilience, WatchdogIsWithheldWhileTheCameraHangs) {
  TempDir dir;
  NotifySocket sock(dir.path() / "notify.sock");
  const auto conf = dir.path() / "garmcapd.toml";
  // Hung after 3 x capture_timeout_ms + 5 s in "capturing" (Station::healthy): 5.3 s here.
  std::ofstream(conf) << "[camera]\ncapture_timeout_ms = 100\n";
  const int kWatchdogUs = 400000;
  Daemon d(dir.path() / "data", DaemonOptions{{"--config", conf.string()},
                                              {},
                                              {{"NOTIFY_SOCKET", sock.path()},
                                               {"WATCHDOG_USEC", std::to_string(kWatchdogUs)}},
                                              {}});
  ASSERT_TRUE(NotifySocket::has(
      sock.collect(5s, [](const auto& m) { return NotifySocket::has(m, "READY=1"); }), "READY=1"));
  ASSERT_EQ(d.post("/api/sim/camera", R"({"still_delay_ms": 8000})").status, 200);
  const double captureSent = secondsSince(sock.made());
  const std::int64_t job = d.post("/api/capture/empty").json()["job"];
  // While the still hangs the API still answers and reports the station unhealthy.
  bool sawUnhealthy = false;
  const auto deadline = Clock::now() + 7500ms;
  while (Clock::now() < deadline) {
    sock.collect(100ms);
    auto s = d.get("/api/status");
    ASSERT_EQ(s.status, 200) << "the API must answer while the camera hangs";
    sawUnhealthy |= s.json()["healthy"] == false;
  }
  EXPECT_TRUE(sawUnhealthy);
  ASSERT_EQ(d.post("/api/sim/camera", R"({"still_delay_ms": 0})").status, 200);
  // Keep reading the notify socket while waiting: a full datagram queue (net.unix.max_dgram_qlen,
  // 10 by default) would block the daemon's sd_notify, as an unresponsive systemd would.
  Json j = Json::object();
  const auto jobDeadline = Clock::now() + 60s;
  while (Clock::now() < jobDeadline && j.value("state", "") != "done" &&
         j.value("state", "") != "failed") {
    sock.collect(100ms);
    if (auto r = d.get("/api/jobs/" + std::to_string(job)).json(); r.is_object())
      j = r;
  }
  EXPECT_TRUE(j["state"] == "done" || j["state"] == "failed") << j.dump();
  sock.collect(1500ms);
  const auto pings = pingTimes(sock.collect(0ms));
  const auto [gap, gapStart] = longestGapEndingIn(pings, captureSent, 1e9);
  std::printf("[watchdog] still hung 8 s: pings withheld for %.0f ms from %.1f s into it\n",
              gap * 1000, gapStart - captureSent);
  EXPECT_GT(gap, kWatchdogUs / 1e6) << "systemd would not have restarted a hung camera";
  EXPECT_GE(gap, 1.5);
  EXPECT_GE(gapStart - captureSent, 4.5) << "withheld before the camera's limit";
  EXPECT_GE(std::count_if(pings.begin(), pings.end(), [&](double t) { return t > gapStart + gap; }),
            3)
      << "pings did not resume once the camera answered";
  EXPECT_EQ(d.terminate(), 0);
}

// --- SIGHUP -----------------------------------------------------------------------------------

TEST(DaemonResilience, SighupReloadsAndAnInvalidFileKeepsTheRunningConfig) {
  TempDir dir;
  NotifySocket sock(dir.path() / "notify.sock");
  const auto conf = dir.path() / "garmcapd.toml";
  const auto log = dir.path() / "garmcapd.log";
  std::ofstream(conf) << "[pipeline]\nreview_below_confidence = 0.5\nqueue_limit = 8\n";
  Daemon d(dir.path() / "data",
           DaemonOptions{{"--config", conf.string()}, {}, {{"NOTIFY_SOCKET", sock.path()}}, log});
  auto config = [&] { return d.get("/api/status").json()["config"]; };
  ASSERT_EQ(config()["queue_limit"], 8);
  sock.collect(5s, [](const auto& m) { return NotifySocket::has(m, "READY=1"); });
  auto waitReloads = [&](int n) {
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline && config()["reloads"] != n)
      std::this_thread::sleep_for(20ms);
    return config()["reloads"] == n;
  };
  auto waitLog = [&](const std::string& text) {
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline && readAll(log).find(text) == std::string::npos)
      std::this_thread::sleep_for(20ms);
    return readAll(log).find(text) != std::string::npos;
  };

  // A valid change applies at once; one that needs a restart is named, not applied.
  std::ofstream(conf) << "[pipeline]\nreview_below_confidence = 0.9\nqueue_limit = 3\n"
                         "worker_threads = 2\n[naming]\ntemplate = \"{id}_{kind}\"\n";
  d.signal(SIGHUP);
  ASSERT_TRUE(waitReloads(1));
  EXPECT_EQ(config()["review_below_confidence"], 0.9);
  EXPECT_EQ(config()["queue_limit"], 3);
  EXPECT_EQ(config()["naming_template"], "{id}_{kind}");
  EXPECT_TRUE(waitLog("[pipeline] worker_threads changed")) << readAll(log);

  // Invalid files: refused with the file, key and reason; the running config stays.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"[pipeline]\nreview_below_confidence = 2.5\n",
       "[pipeline] review_below_confidence: must be in [0, 1], got 2.5"},
      {"[pipeline]\ncolour = \"red\"\n", "[pipeline] colour: unknown key"},
      {"[pipeline]\nqueue_limit = \"many\"\n", "[pipeline] queue_limit: must be an integer"},
      {"[pipeline\n", conf.string()},
  };
  auto refusals = [&] {
    std::vector<std::string> lines;
    std::istringstream in(readAll(log));
    for (std::string line; std::getline(in, line);)
      if (line.find("reload refused") != std::string::npos)
        lines.push_back(line);
    return lines;
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    std::ofstream(conf) << bad[i].first;
    d.signal(SIGHUP);
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline && refusals().size() <= i)
      std::this_thread::sleep_for(20ms);
    const auto lines = refusals();
    ASSERT_EQ(lines.size(), i + 1) << readAll(log);
    EXPECT_NE(lines[i].find("keeping the running config: " + conf.string()), std::string::npos)
        << lines[i];
    EXPECT_NE(lines[i].find(bad[i].second), std::string::npos) << lines[i];
  }
  EXPECT_EQ(config()["reloads"], 1);
  EXPECT_EQ(config()["review_below_confidence"], 0.9);
  EXPECT_EQ(config()["queue_limit"], 3);
  // systemd saw each reload begin and end.
  const auto& ms = sock.collect(2000ms, [](const auto& m) {
    return std::count_if(m.begin(), m.end(), [](const auto& x) {
             return x.text.find("RELOADING=1") != std::string::npos;
           }) >= 5;
  });
  EXPECT_EQ(std::count_if(ms.begin(), ms.end(),
                          [](const auto& x) { return x.text.find("RELOADING=1") == 0; }),
            5);
  EXPECT_FALSE(NotifySocket::has(ms, "WATCHDOG=1")) << "no WATCHDOG_USEC, no pings";
  EXPECT_EQ(d.terminate(), 0);
}

// The size chart comes from the configuration and a SIGHUP changes it for the captures that
// follow: the size guide of the next item is graded to the new chart (the processor is swapped
// between jobs and prepares the calibration again with the new chart's body). A chart the
// station does not know is refused at reload, naming the known ones, and the running chart kept.
TEST(DaemonResilience, SighupChangesTheSizeChartOfTheNextCapture) {
  TempDir dir;
  const auto conf = dir.path() / "garmcapd.toml";
  const auto log = dir.path() / "garmcapd.log";
  std::ofstream(conf) << "[pipeline]\nsize_chart = \"korean_women\"\n";
  DaemonOptions o{{"--config", conf.string()}, {}, {}, log};
  o.synthetic = true;
  Daemon d(dir.path() / "data", o);
  auto config = [&] { return d.get("/api/status").json()["config"]; };
  ASSERT_EQ(config()["size_chart"], "korean_women");
  ASSERT_EQ(d.waitJob(d.post("/api/button").json()["job"])["state"], "done");
  // The chart of the next item with a size guide (a garment without a pattern has none).
  auto nextGuideChart = [&]() -> std::string {
    for (int i = 0; i < 4; ++i) {
      const auto job = d.waitJob(d.post("/api/button").json()["job"]);
      if (job["state"] != "done")
        continue;
      const auto guide = d.get("/api/items/" + job["item_id"].dump() + "/sizeguide.json");
      if (guide.status == 200)
        return guide.json().value("chart", "");
    }
    return "";
  };
  EXPECT_EQ(nextGuideChart(), "korean_women");

  std::ofstream(conf) << "[pipeline]\nsize_chart = \"italian_women\"\n";
  d.signal(SIGHUP);
  const auto deadline = Clock::now() + 10s;
  while (Clock::now() < deadline && config()["reloads"] != 1)
    std::this_thread::sleep_for(20ms);
  ASSERT_EQ(config()["reloads"], 1);
  EXPECT_EQ(config()["size_chart"], "italian_women");
  EXPECT_EQ(nextGuideChart(), "italian_women");

  std::ofstream(conf) << "[pipeline]\nsize_chart = \"korean_men\"\n";
  d.signal(SIGHUP);
  const auto refused = Clock::now() + 10s;
  while (Clock::now() < refused && readAll(log).find("reload refused") == std::string::npos)
    std::this_thread::sleep_for(20ms);
  EXPECT_NE(readAll(log).find("[pipeline] size_chart: unknown size chart 'korean_men' (known "
                              "charts: korean_women, italian_women, french_women)"),
            std::string::npos)
      << readAll(log);
  EXPECT_EQ(config()["size_chart"], "italian_women");
  EXPECT_EQ(nextGuideChart(), "italian_women");
  EXPECT_EQ(d.terminate(), 0);
}

}  // namespace
}  // namespace garmcap::e2e
