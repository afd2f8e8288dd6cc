// The hub end to end: a real PostgreSQL (temp_postgres.h), the real garmcap-hub and two real
// simulated stations (garmcapd --simulated) on loopback. Captures on each arrive at the hub; the
// hub stops, the stations capture on, it starts again and everything arrives; a station killed
// with SIGKILL while its outbox is being sent comes back and every item is at the hub exactly
// once with every blob's hash right; an edit made at the hub reaches the station.
#include <gtest/gtest.h>

#include <sstream>

#include "../common/test_certs.h"
#include "../e2e/daemon_harness.h"
#include "garmcap/daemon/content_store.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

using namespace garmcap::e2e;
const std::string kHubBin = std::string(GARMCAP_BIN_DIR) + "/garmcap-hub";
const std::string kAdmin = "admin-token-0123456789";

// garmcap-hub as a child process; started on a fixed port so that it can come back on it.
class HubProcess {
 public:
  HubProcess(const std::string& db, int port, const std::vector<std::string>& stations,
             const std::filesystem::path& log, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {kHubBin,
                                     "--db",
                                     db,
                                     "--listen",
                                     "127.0.0.1:" + std::to_string(port),
                                     "--admin-token-sha256",
                                     daemon::sha256Hex(kAdmin)};
    for (const auto& s : stations)
      args.insert(args.end(), {"--station", s});
    args.insert(args.end(), extra.begin(), extra.end());
    int out[2];
    if (pipe(out) != 0)
      throw std::runtime_error("pipe");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], 1);
      close(out[0]);
      close(out[1]);
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      dup2(fd, 2);
      std::vector<char*> argv;
      for (auto& a : args)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(kHubBin.c_str(), argv.data());
      _exit(127);
    }
    close(out[1]);
    std::string text;
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    fcntl(out[0], F_SETFL, O_NONBLOCK);
    while (std::chrono::steady_clock::now() < deadline &&
           text.find("garmcap-hub listening on") == std::string::npos) {
      char c[256];
      const ssize_t n = read(out[0], c, sizeof c);
      if (n > 0)
        text.append(c, static_cast<std::size_t>(n));
      else if (n == 0)
        break;
      else
        std::this_thread::sleep_for(10ms);
    }
    close(out[0]);
    if (text.find("garmcap-hub listening on") == std::string::npos)
      throw std::runtime_error("garmcap-hub did not start: '" + text + "' (log " + log.string() +
                               ")");
  }
  ~HubProcess() { stop(); }
  void kill9() {
    ::kill(pid_, SIGKILL);
    int st = 0;
    waitpid(pid_, &st, 0);
    pid_ = -1;
  }
  int stop() {
    if (pid_ <= 0)
      return -1;
    ::kill(pid_, SIGTERM);
    int st = 0;
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    while (waitpid(pid_, &st, WNOHANG) != pid_) {
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid_, SIGKILL);  // a hub that does not stop is a failure, not a hang
        waitpid(pid_, &st, 0);
        pid_ = -1;
        return -1;
      }
      std::this_thread::sleep_for(20ms);
    }
    pid_ = -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  }

 private:
  pid_t pid_ = -1;
};

Reply admin(int port, http::verb verb, const std::string& target, const std::string& body = "") {
  std::vector<std::pair<std::string, std::string>> fields = {{"Host", "127.0.0.1"},
                                                             {"Authorization", "Bearer " + kAdmin}};
  if (!body.empty())
    fields.emplace_back("Content-Type", "application/json");
  return httpCallWith(port, verb, target, fields, body);
}

// Every live hub item of a station: local id -> item JSON (all pages).
std::map<std::int64_t, Json> hubItems(int port, const std::string& station) {
  std::map<std::int64_t, Json> out;
  std::string after;
  for (int page = 0; page < 100; ++page) {
    auto r =
        admin(port, http::verb::get,
              "/api/items?limit=50&station=" + station + (after.empty() ? "" : "&after=" + after));
    if (r.status != 200)
      return out;
    const Json j = r.json();
    for (const auto& it : j["items"])
      out[it["local_id"].get<std::int64_t>()] = it;
    if (j["next"].is_null())
      break;
    after = j["next"].dump();
  }
  return out;
}

bool waitFor(const std::function<bool()>& done, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done())
      return true;
    std::this_thread::sleep_for(50ms);
  }
  return done();
}

std::int64_t captureOne(const Daemon& d, const std::string& sku) {
  auto r = d.post("/api/capture", R"({"sku": ")" + sku + "\"}");
  if (r.status != 202)
    throw std::runtime_error("capture refused: " + r.body);
  auto job = d.waitJob(r.json()["job"], 120s);
  if (job["state"] != "done")
    throw std::runtime_error("capture failed: " + job.dump());
  return job["item_id"].get<std::int64_t>();
}

std::int64_t count(const std::filesystem::path& db, const char* sql) {
  const auto v = column(db, sql);
  return v.empty() ? -1 : std::stoll(v[0]);
}

// A transaction that holds the row lock every push of `station` takes at the hub (its row of
// `stations`), until destroyed: a push of that station then waits inside the hub.
class StationLock {
 public:
  StationLock(const test::TempPostgres& pg, std::string db, const std::string& station)
      : pg_(pg), db_(std::move(db)), name_("lock_" + station) {
    thread_ = std::thread([this, station] {
      try {
        pg_.psql(db_, "SET application_name = '" + name_ +
                          "'; BEGIN; SELECT 1 FROM stations WHERE id = '" + station +
                          "' FOR UPDATE; SELECT pg_sleep(60);");
      } catch (const std::exception&) {
        // terminated by the destructor, as intended
      }
    });
  }
  ~StationLock() {
    pg_.psql(db_,
             "SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE "
             "application_name = '" +
                 name_ + "'");
    thread_.join();
  }
  /// Waits until the lock is taken (bounded).
  bool held() const {
    return waitFor(
        [&] {
          return pg_.psql(db_, "SELECT count(*) FROM pg_stat_activity WHERE application_name = '" +
                                   name_ + "' AND wait_event = 'PgSleep'") == "1";
        },
        20s);
  }
  /// True once a statement waits for a lock on `stations` (a push waiting for this one).
  bool waitedOn(std::chrono::seconds limit) const {
    return waitFor(
        [&] {
          return pg_.psql(db_,
                          "SELECT count(*) FROM pg_stat_activity WHERE wait_event_type = "
                          "'Lock' AND query LIKE '%FROM stations%'") != "0";
        },
        limit);
  }

 private:
  const test::TempPostgres& pg_;
  std::string db_, name_;
  std::thread thread_;
};

struct StationSetup {
  std::string name, token;
  std::filesystem::path data, config;
};

// shop1 and shop2 in `dir`, each with its data folder and a config pushing to `hubUrl` (plus
// `extra(station)`, lines of its [hub] section), and the hub's --station arguments for them.
struct Stations {
  std::vector<StationSetup> setups;
  std::vector<std::string> hubArgs;
};

Stations twoStations(const std::filesystem::path& dir, const std::string& hubUrl,
                     const std::function<std::string(const StationSetup&)>& extra = {}) {
  Stations out;
  out.setups = {{"shop1", "token-of-shop1-abcdef", dir / "s1", {}},
                {"shop2", "token-of-shop2-abcdef", dir / "s2", {}}};
  for (auto& s : out.setups) {
    std::filesystem::create_directories(s.data);
    s.config = dir / (s.name + ".toml");
    std::ofstream(s.config) << "[hub]\nurl = \"" << hubUrl << "\"\ntoken = \"" << s.token
                            << "\"\npoll_ms = 100\n"
                            << (extra ? extra(s) : std::string());
    out.hubArgs.push_back(s.name + "=" + daemon::sha256Hex(s.token));
  }
  return out;
}

// How a station of twoStations runs: its config, the simulated rig, its log in `dir`.
DaemonOptions stationOptions(const StationSetup& s, const std::filesystem::path& dir,
                             const std::filesystem::path& rig) {
  DaemonOptions o;
  o.args = {"--config", s.config.string()};
  o.rig = rig;
  o.stderrFile = dir / (s.name + ".log");
  return o;
}

TEST(HubE2E, TwoStationsPushThroughHubDowntimeAndAKillEveryItemOnce) {
  if (!test::postgresBinDir())
    GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql "
                    "(apt install postgresql-15; ./station.sh deps installs it)";
  const auto t0 = std::chrono::steady_clock::now();
  TempDir dir;
  test::TempPostgres pg;
  const std::string db = "hub_e2e";
  pg.createDatabase(db);
  const int hubPort = test::freeLoopbackPort();
  const auto rig = makeSimulatedRig(dir.path());
  auto [setups, stationArgs] =
      twoStations(dir.path(), "http://127.0.0.1:" + std::to_string(hubPort));
  auto options = [&](const StationSetup& s) { return stationOptions(s, dir.path(), rig); };
  const auto hubLog = dir.path() / "hub.log";
  auto hub = std::make_unique<HubProcess>(pg.url("hub_e2e"), hubPort, stationArgs, hubLog);
  auto a = std::make_unique<Daemon>(setups[0].data, options(setups[0]));
  auto b = std::make_unique<Daemon>(setups[1].data, options(setups[1]));
  for (auto* d : {a.get(), b.get()})
    ASSERT_EQ(d->waitJob(d->post("/api/capture/empty").json()["job"])["state"], "done");

  // 1. Captures on each station arrive at the hub.
  std::vector<std::int64_t> itemsA = {captureOne(*a, "A-1"), captureOne(*a, "A-2")};
  std::vector<std::int64_t> itemsB = {captureOne(*b, "B-1")};
  ASSERT_TRUE(waitFor(
      [&] {
        return hubItems(hubPort, "shop1").size() == 2 && hubItems(hubPort, "shop2").size() == 1;
      },
      30s))
      << "hub log: " << hubLog;
  const auto first = hubItems(hubPort, "shop1").at(itemsA[0]);
  EXPECT_EQ(first["sku"], "A-1");
  EXPECT_FALSE(first["measurements"].empty());
  EXPECT_TRUE(first["images"].contains("dressed")) << first.dump();

  // 2. The hub stops; the stations capture on and keep the changes in their outbox.
  EXPECT_EQ(hub->stop(), 0);
  itemsA.push_back(captureOne(*a, "A-3"));
  itemsB.push_back(captureOne(*b, "B-2"));
  EXPECT_GE(count(setups[0].data / "catalog.sqlite", "SELECT count(*) FROM outbox"), 1);
  EXPECT_GE(count(setups[1].data / "catalog.sqlite", "SELECT count(*) FROM outbox"), 1);
  itemsA.push_back(captureOne(*a, "A-4"));
  itemsA.push_back(captureOne(*a, "A-5"));

  // 3. The hub comes back; station A is killed (SIGKILL) in the middle of a push, then
  // restarts on the same data. To be sure the kill lands mid-push, a transaction holds the lock
  // that a push of shop1 takes at the hub (its station row): A's blobs go in, its POST waits at
  // the hub, and A is killed while it waits. The hub then commits that push, whose answer A never
  // read: A sends it again after its restart, and it must still be one item.
  auto holder = std::make_unique<StationLock>(pg, db, "shop1");
  ASSERT_TRUE(holder->held());
  const auto itemsBefore = pg.psql(db, "SELECT count(*) FROM items WHERE station_id = 'shop1'");
  hub = std::make_unique<HubProcess>(pg.url("hub_e2e"), hubPort, stationArgs, hubLog);
  const bool blocked = holder->waitedOn(40s);
  a->kill9();
  const auto pendingAtKill =
      count(setups[0].data / "catalog.sqlite", "SELECT count(*) FROM outbox");
  holder.reset();
  ASSERT_TRUE(blocked) << "A's push never reached the hub's lock";
  std::printf(
      "[hub e2e] station A killed while its push waited at the hub, %lld outbox row(s) "
      "unsent\n",
      static_cast<long long>(pendingAtKill));
  EXPECT_EQ(pendingAtKill, 3);  // A-3, A-4, A-5: none acknowledged
  // The hub commits the push A was killed in (its answer went nowhere).
  EXPECT_TRUE(waitFor(
      [&] {
        return pg.psql(db, "SELECT count(*) FROM items WHERE station_id = 'shop1'") != itemsBefore;
      },
      10s));
  a = std::make_unique<Daemon>(setups[0].data, options(setups[0]));
  ASSERT_TRUE(waitFor(
      [&] {
        return hubItems(hubPort, "shop1").size() == itemsA.size() &&
               hubItems(hubPort, "shop2").size() == itemsB.size();
      },
      30s));
  ASSERT_TRUE(waitFor(
      [&] {
        return count(setups[0].data / "catalog.sqlite", "SELECT count(*) FROM outbox") == 0 &&
               count(setups[1].data / "catalog.sqlite", "SELECT count(*) FROM outbox") == 0;
      },
      30s));

  // 3b. The hub is killed (SIGKILL) in the middle of a write: B's push waits inside the hub's
  // transaction when the hub dies. Nothing of it is committed; B retries, and once the hub is
  // back the item is there, once.
  {
    auto lockB = std::make_unique<StationLock>(pg, db, "shop2");
    ASSERT_TRUE(lockB->held());
    itemsB.push_back(captureOne(*b, "B-3"));
    ASSERT_TRUE(lockB->waitedOn(30s)) << "B's push never reached the hub";
    hub->kill9();
    lockB.reset();
    EXPECT_EQ(pg.psql(db, "SELECT count(*) FROM items WHERE station_id = 'shop2'"),
              std::to_string(itemsB.size() - 1));
    hub = std::make_unique<HubProcess>(pg.url("hub_e2e"), hubPort, stationArgs, hubLog);
    ASSERT_TRUE(waitFor([&] { return hubItems(hubPort, "shop2").size() == itemsB.size(); }, 40s));
    ASSERT_TRUE(waitFor(
        [&] {
          return count(setups[1].data / "catalog.sqlite", "SELECT count(*) FROM outbox") == 0;
        },
        30s));
  }

  // Every item exactly once, under its station and local id; every blob's bytes hash to its
  // name (PostgreSQL's own sha256), and each station's images are all at the hub.
  EXPECT_EQ(pg.psql(db, "SELECT count(*) FROM items"),
            std::to_string(itemsA.size() + itemsB.size()));
  EXPECT_EQ(pg.psql(db,
                    "SELECT count(*) FROM (SELECT station_id, local_id FROM items GROUP BY 1, "
                    "2 HAVING count(*) > 1) d"),
            "0");
  EXPECT_EQ(pg.psql(db, "SELECT count(*) FROM images WHERE encode(sha256(bytes), 'hex') <> sha256"),
            "0");
  for (const auto& s : setups) {
    const auto local = column(s.data / "catalog.sqlite",
                              "SELECT DISTINCT sha256 FROM item_images ORDER BY sha256");
    const auto atHub =
        pg.psql(db,
                "SELECT string_agg(DISTINCT ii.sha256, ',' ORDER BY ii.sha256) FROM item_images ii "
                "JOIN items i ON i.id = ii.item_id WHERE i.station_id = '" +
                    s.name + "'");
    std::string joined;
    for (const auto& sha : local)
      joined += (joined.empty() ? "" : ",") + sha;
    EXPECT_FALSE(local.empty());
    EXPECT_EQ(atHub, joined) << s.name;
    // The blob the hub serves is the station's file, byte for byte.
    const auto blob = admin(hubPort, http::verb::get, "/api/hub/blobs/" + local.front());
    ASSERT_EQ(blob.status, 200);
    EXPECT_EQ(daemon::sha256Hex(blob.body), local.front());
  }
  // The patterns came with the items: the same (item, size) pairs as each station's, and one
  // served as pattern.json is the station's JSON.
  for (const auto& s : setups) {
    const auto local =
        column(s.data / "catalog.sqlite", "SELECT item_id || ':' || size FROM patterns ORDER BY 1");
    std::string joined;
    for (const auto& p : local)
      joined += (joined.empty() ? "" : ",") + p;
    EXPECT_FALSE(local.empty()) << s.name << ": the simulated captures draft no pattern";
    EXPECT_EQ(pg.psql(db,
                      "SELECT string_agg(i.local_id || ':' || p.size, ',' ORDER BY "
                      "i.local_id || ':' || p.size) FROM item_patterns p JOIN items i ON "
                      "i.id = p.item_id WHERE i.station_id = '" +
                          s.name + "'"),
              joined)
        << s.name;
  }
  {
    const auto localJson = column(setups[0].data / "catalog.sqlite",
                                  "SELECT json FROM patterns ORDER BY item_id, size LIMIT 1");
    const auto which = column(setups[0].data / "catalog.sqlite",
                              "SELECT item_id || ' ' || size FROM patterns ORDER BY item_id, size "
                              "LIMIT 1");
    ASSERT_EQ(localJson.size(), 1u);
    std::istringstream w(which.front());
    std::int64_t localId = 0;
    std::string size;
    w >> localId >> size;
    const std::string hubId =
        pg.psql(db, "SELECT id FROM items WHERE station_id = 'shop1' AND local_id = " +
                        std::to_string(localId));
    const auto served =
        admin(hubPort, http::verb::get, "/api/items/" + hubId + "/pattern.json?size=" + size);
    ASSERT_EQ(served.status, 200) << served.body;
    EXPECT_EQ(Json::parse(served.body), Json::parse(localJson.front()));
  }

  // 4. An edit at the hub (approval with a title and a price) reaches the station, and is not
  // sent back as a change of the station's.
  const auto target = hubItems(hubPort, "shop1").at(itemsA[1]);
  const auto patch = admin(hubPort, http::verb::patch, "/api/items/" + target["id"].dump(),
                           R"({"status": "approved", "title": "Hub title", "price_cents": 4500})");
  ASSERT_EQ(patch.status, 200) << patch.body;
  const std::string localUrl = "/api/items/" + std::to_string(itemsA[1]);
  ASSERT_TRUE(waitFor(
      [&] {
        const Json it = a->get(localUrl).json();
        return it.is_object() && it.value("title", "") == "Hub title" &&
               it["price_cents"] == 4500 && it.value("status", "") == "approved";
      },
      20s))
      << a->get(localUrl).body;
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(count(setups[0].data / "catalog.sqlite", "SELECT count(*) FROM outbox"), 0);
  // A station-side rename after approval: the hub keeps its title and the station comes round.
  ASSERT_EQ(
      httpCall(a->port(), http::verb::patch, localUrl, R"({"title": "Station rename"})").status,
      200);
  ASSERT_TRUE(waitFor(
      [&] {
        const Json it = a->get(localUrl).json();
        return it.is_object() && it.value("title", "") == "Hub title";
      },
      20s));
  EXPECT_EQ(hubItems(hubPort, "shop1").at(itemsA[1])["title"], "Hub title");

  // Wrong tokens are refused at the hub.
  EXPECT_EQ(httpCallWith(hubPort, http::verb::get, "/api/items",
                         {{"Host", "127.0.0.1"}, {"Authorization", "Bearer nope"}})
                .status,
            401);
  EXPECT_EQ(a->terminate(), 0);
  EXPECT_EQ(b->terminate(), 0);
  EXPECT_EQ(hub->stop(), 0);
  std::printf("[hub e2e] %zu + %zu items, whole test %.1f s\n", itemsA.size(), itemsB.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// Over TLS: garmcap-hub serving HTTPS with a certificate made at test time, a station that
// trusts its CA pushes a capture; a station configured with another CA pushes nothing, keeps
// its outbox and says why in its /api/status.
TEST(HubE2E, AStationPushesOverTlsAndOneWithAnotherCaReportsWhy) {
  if (!test::postgresBinDir())
    GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql "
                    "(apt install postgresql-15; ./station.sh deps installs it)";
  TempDir dir;
  const garmcap::test::TestCerts certs(dir.path() / "tls");
  test::TempPostgres pg;
  const std::string db = "hub_tls_e2e";
  pg.createDatabase(db);
  const int hubPort = test::freeLoopbackPort();
  const auto rig = makeSimulatedRig(dir.path());
  auto [setups, stationArgs] = twoStations(
      dir.path(), "https://127.0.0.1:" + std::to_string(hubPort), [&](const StationSetup& s) {
        const auto& ca = s.name == "shop1" ? certs.caCert : certs.otherCaCert;
        return "ca_file = \"" + ca.string() + "\"\n";
      });
  const auto hubLog = dir.path() / "hub.log";
  HubProcess hub(pg.url(db), hubPort, stationArgs, hubLog,
                 {"--tls-cert", certs.serverCert.string(), "--tls-key", certs.serverKey.string()});
  auto options = [&](const StationSetup& s) { return stationOptions(s, dir.path(), rig); };
  Daemon a(setups[0].data, options(setups[0]));
  Daemon b(setups[1].data, options(setups[1]));
  for (auto* d : {&a, &b})
    ASSERT_EQ(d->waitJob(d->post("/api/capture/empty").json()["job"])["state"], "done");
  const std::int64_t itemA = captureOne(a, "TLS-A");
  captureOne(b, "TLS-B");
  ASSERT_TRUE(waitFor(
      [&] {
        return pg.psql(db, "SELECT count(*) FROM items WHERE station_id = 'shop1' AND local_id = " +
                               std::to_string(itemA)) == "1";
      },
      30s))
      << "hub log: " << hubLog << ", station log: " << dir.path() / "shop1.log";
  // Its image went too, byte-exact.
  EXPECT_EQ(pg.psql(db, "SELECT count(*) FROM images WHERE encode(sha256(bytes), 'hex') <> sha256"),
            "0");
  EXPECT_NE(pg.psql(db, "SELECT count(*) FROM images"), "0");
  Json statusB;
  ASSERT_TRUE(waitFor(
      [&] {
        statusB = b.get("/api/status").json();
        return statusB.contains("hub") && statusB["hub"].value("tls_error", Json()).is_string();
      },
      30s))
      << statusB.dump();
  const std::string why = statusB["hub"]["tls_error"].get<std::string>();
  EXPECT_NE(why.find("unable to get local issuer certificate"), std::string::npos) << why;
  EXPECT_GE(statusB["hub"]["outbox"].get<std::int64_t>(), 1) << statusB.dump();
  EXPECT_EQ(statusB["hub"]["refused_count"].get<std::int64_t>(), 0) << statusB.dump();
  EXPECT_EQ(pg.psql(db, "SELECT count(*) FROM items WHERE station_id = 'shop2'"), "0");
  EXPECT_TRUE(a.get("/api/status").json()["hub"]["tls_error"].is_null());
}

}  // namespace
}  // namespace garmcap::hub
