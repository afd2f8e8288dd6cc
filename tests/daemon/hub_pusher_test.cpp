// The pusher's retry schedule and the [hub] configuration (the pushing itself runs against the
// real hub in tests/hub/hub_e2e_test.cpp).
#include "garmcap/daemon/hub_pusher.h"

#include <gtest/gtest.h>

#include <boost/asio/post.hpp>
#include <fstream>
#include <map>
#include <thread>

#include "../common/test_certs.h"
#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/http_server.h"
#include "garmcap/daemon/tls_context.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

using std::chrono::milliseconds;

TEST(HubPusher, BackoffDoublesFromHalfASecondToThirtySeconds) {
  EXPECT_EQ(hubBackoff(0), milliseconds(0));
  EXPECT_EQ(hubBackoff(1), milliseconds(500));
  EXPECT_EQ(hubBackoff(2), milliseconds(1000));
  EXPECT_EQ(hubBackoff(3), milliseconds(2000));
  EXPECT_EQ(hubBackoff(7), milliseconds(30000));  // 32 s capped
  EXPECT_EQ(hubBackoff(1000), milliseconds(30000));
}

TEST(HubConfig, UrlIsHttpsOrHttpHostPortAndNeedsAToken) {
  auto a = parseHubUrl("http://127.0.0.1:8090");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 8090);
  EXPECT_FALSE(a->tls);
  EXPECT_TRUE(parseHubUrl("http://hub.local:80/"));
  auto s = parseHubUrl("https://hub.example-chain.net:8443/");
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->tls);
  EXPECT_EQ(s->host, "hub.example-chain.net");
  EXPECT_EQ(s->port, 8443);
  EXPECT_EQ(s->url(), "https://hub.example-chain.net:8443");
  for (const char* bad :
       {"https://127.0.0.1", "http://127.0.0.1", "http://:80", "http://h:0", "http://h:70000",
        "http://h:80/api", "ftp://h:1", "http://h h:80", "https//h:1", "httpx://h:1"})
    EXPECT_FALSE(parseHubUrl(bad)) << bad;
  test::TempDir dir;
  const auto file = dir.path() / "c.toml";
  std::ofstream(file) << "[hub]\nurl = \"http://127.0.0.1:8090\"\ntoken = \"t\"\npoll_ms = 100\n";
  Config c = loadConfig(file);
  EXPECT_EQ(c.hubUrl, "http://127.0.0.1:8090");
  EXPECT_EQ(c.hubToken, "t");
  EXPECT_EQ(c.hubPollMs, 100);
  EXPECT_NO_THROW(c.validate());
  c.hubToken.clear();
  EXPECT_THROW(c.validate(), ConfigError);
  std::ofstream(file) << "[hub]\nurl = \"ftp://hub:443\"\n";
  try {
    loadConfig(file);
    FAIL() << "ftp:// must be refused";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[hub] url"), std::string::npos) << e.what();
  }
}

TEST(HubConfig, CaFileGoesWithAnHttpsUrlAndMustExist) {
  test::TempDir dir;
  const auto file = dir.path() / "c.toml";
  const auto ca = dir.path() / "ca.pem";
  std::ofstream(ca) << "not checked here\n";
  std::ofstream(file) << "[hub]\nurl = \"https://127.0.0.1:8443\"\ntoken = \"t\"\nca_file = \""
                      << ca.string() << "\"\n";
  Config c = loadConfig(file);
  EXPECT_EQ(c.hubCaFile, ca.string());
  EXPECT_NO_THROW(c.validate());
  c.hubCaFile = (dir.path() / "missing.pem").string();
  try {
    c.validate();
    FAIL() << "a missing CA file must be refused";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[hub] ca_file: " + c.hubCaFile + ": no such file"),
              std::string::npos)
        << e.what();
  }
  c.hubCaFile = ca.string();
  c.hubUrl = "http://127.0.0.1:8090";
  EXPECT_THROW(c.validate(), ConfigError);  // a CA for a plain-HTTP hub is a mistake
}

}  // namespace
}  // namespace garmcap::daemon

// --- the pusher against a scripted hub (HTTP on loopback), with a real catalog -----------------

namespace garmcap::daemon {
namespace {

// The station side the pusher needs: the catalog (behind a mutex, as the strand would serialise
// it) and the content store.
class CatalogOnlyStation : public RouteContext {
 public:
  explicit CatalogOnlyStation(const std::filesystem::path& dir)
      : catalog_(dir / "catalog.db"), store_(dir / "store") {}
  void withCatalog(std::function<void(Catalog&)> fn, Reply) override {
    std::lock_guard lock(mutex_);
    fn(catalog_);
  }
  void offload(std::function<void()> fn, Reply) override { fn(); }
  const ContentStore& store() const override { return store_; }
  std::string namingTemplate() const override { return "{sku}"; }
  int markerMaxPieces() const override { return 60; }
  ShopConfig shopConfig() const override { return {}; }
  nlohmann::json savedShopSettings() const override { return nlohmann::json::object(); }
  ShopConfig saveShopSettings(Catalog&, const nlohmann::json&) override { return {}; }
  template <typename T>
  T read(const std::function<T(Catalog&)>& fn) {
    std::lock_guard lock(mutex_);
    return fn(catalog_);
  }

 private:
  std::mutex mutex_;
  Catalog catalog_;
  ContentStore store_;
};

// Answers pushes as a hub would: `refuse` maps a local id to the status it is refused with for
// ever; `tokenStatus` (401/403), when set, is every answer.
class ScriptedHub {
 public:
  std::map<std::int64_t, int> refuse;
  std::atomic<int> tokenStatus{0};
  std::atomic<int> blobPuts{0};  // every PUT is answered 413

  // With `tls`, the hub serves HTTPS only.
  explicit ScriptedHub(std::shared_ptr<boost::asio::ssl::context> tls = nullptr)
      : tls_(tls != nullptr) {
    config_.listenAddress = "127.0.0.1";
    config_.listenPort = 0;
    router_.add(http::verb::post, "/api/hub/push",
                [this](const Request& req, const RouteMatch&, Reply reply) {
                  if (tokenStatus)
                    return reply(jsonError(static_cast<http::status>(tokenStatus.load()), "token"));
                  const auto id =
                      nlohmann::json::parse(req.body()).at("local_id").get<std::int64_t>();
                  std::lock_guard lock(mutex_);
                  ++attempts_[id];
                  if (auto r = refuse.find(id); r != refuse.end())
                    return reply(jsonError(static_cast<http::status>(r->second),
                                           "field 'title' is not valid"));
                  accepted_.push_back(id);
                  reply(jsonResponse(http::status::ok, {{"ok", true}}));
                });
    router_.add(http::verb::head, "/api/hub/blobs/{sha}",
                [](const Request&, const RouteMatch&, Reply reply) {
                  reply(jsonError(http::status::not_found, "no such blob"));
                });
    router_.add(http::verb::put, "/api/hub/blobs/{sha}",
                [this](const Request&, const RouteMatch&, Reply reply) {
                  ++blobPuts;
                  reply(jsonError(http::status::payload_too_large, "the body is too large"));
                });
    router_.add(http::verb::get, "/api/hub/changes",
                [this](const Request&, const RouteMatch&, Reply reply) {
                  if (tokenStatus)
                    return reply(jsonError(static_cast<http::status>(tokenStatus.load()), "token"));
                  reply(jsonResponse(http::status::ok,
                                     {{"changes", nlohmann::json::array()}, {"next", 0}}));
                });
    server_ = std::make_unique<HttpServer>(io_, config_, router_, files_, std::move(tls));
    server_->start();
    thread_ = std::thread([this] { io_.run(); });
  }
  ~ScriptedHub() {
    boost::asio::post(io_, [this] { server_->stop(); });
    io_.stop();
    thread_.join();
  }
  std::string url(const std::string& host = "127.0.0.1") const {
    return (tls_ ? "https://" : "http://") + host + ":" + std::to_string(server_->port());
  }
  std::vector<std::int64_t> accepted() {
    std::lock_guard lock(mutex_);
    return accepted_;
  }
  int attempts(std::int64_t id) {
    std::lock_guard lock(mutex_);
    return attempts_[id];
  }

 private:
  bool tls_;
  boost::asio::io_context io_{1};
  Config config_;
  Router router_;
  StaticFiles files_{""};
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  std::mutex mutex_;
  std::vector<std::int64_t> accepted_;
  std::map<std::int64_t, int> attempts_;
};

NewItem plainItem(const std::string& sku) {
  NewItem n;
  n.sku = sku;
  n.title = "Skirt " + sku;
  n.type = "skirt";
  n.measurementsCm = {{"waist_circ", 70.0}};
  n.needsReview = true;
  return n;
}

bool waitFor(const std::function<bool()>& done, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (done())
      return true;
    std::this_thread::sleep_for(milliseconds(20));
  }
  return done();
}

Config pusherConfig(const ScriptedHub& hub) {
  Config c;
  c.hubUrl = hub.url();
  c.hubToken = "t";
  c.hubPollMs = 50;
  return c;
}

TEST(HubPusher, RefusalsThatRetriesCannotChangeAreParkedAndTheQueueGoesOn) {
  EXPECT_TRUE(hubRefusesForGood(422));
  EXPECT_TRUE(hubRefusesForGood(400));
  EXPECT_TRUE(hubRefusesForGood(404));
  EXPECT_TRUE(hubRefusesForGood(409));
  EXPECT_TRUE(hubRefusesForGood(413));
  for (int s : {401, 403, 408, 429, 500, 503})
    EXPECT_FALSE(hubRefusesForGood(s)) << s;
  test::TempDir dir;
  CatalogOnlyStation station(dir.path());
  std::vector<std::int64_t> ids;
  for (const char* sku : {"A", "B", "C", "D"})
    ids.push_back(
        station.read<std::int64_t>([sku](Catalog& c) { return c.addItem(plainItem(sku)); }));
  ScriptedHub hub;
  hub.refuse[ids[1]] = 422;
  hub.refuse[ids[2]] = 409;
  HubPusher pusher(station, pusherConfig(hub));
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return hub.accepted().size() == 2; }, std::chrono::seconds(5)))
      << "the rows behind a refused one were not sent";
  ASSERT_TRUE(waitFor(
      [&] { return station.read<std::int64_t>([](Catalog& c) { return c.outboxSize(); }) == 0; },
      std::chrono::seconds(5)));
  std::this_thread::sleep_for(milliseconds(300));  // a few more passes: no retry of a parked row
  pusher.stop();
  EXPECT_EQ(hub.accepted(), (std::vector<std::int64_t>{ids[0], ids[3]}));
  EXPECT_EQ(hub.attempts(ids[1]), 1);
  EXPECT_EQ(hub.attempts(ids[2]), 1);
  const auto refused =
      station.read<std::vector<RefusedOutboxEntry>>([](Catalog& c) { return c.refusedOutbox(); });
  ASSERT_EQ(refused.size(), 2u);
  EXPECT_EQ(refused[0].row.itemId, ids[2]);  // newest first
  EXPECT_EQ(refused[0].httpStatus, 409);
  EXPECT_EQ(refused[1].row.itemId, ids[1]);
  EXPECT_EQ(refused[1].httpStatus, 422);
  EXPECT_NE(refused[1].reason.find("field 'title' is not valid"), std::string::npos)
      << refused[1].reason;
  EXPECT_EQ(pusher.counters().refused.load(), 2);
  EXPECT_TRUE(pusher.tokenRefused().empty());
}

TEST(HubPusher, ABlobTheHubRefusesForGoodParksItsItem) {
  test::TempDir dir;
  CatalogOnlyStation station(dir.path());
  const std::string bytes(4096, '\x42');
  const std::string sha = station.store().put(bytes);
  NewItem withImage = plainItem("A");
  withImage.images = {{"dressed", sha, "image/png", static_cast<std::int64_t>(bytes.size())}};
  const auto a = station.read<std::int64_t>([&](Catalog& c) { return c.addItem(withImage); });
  const auto b = station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("B")); });
  ScriptedHub hub;
  HubPusher pusher(station, pusherConfig(hub));
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return hub.accepted().size() == 1; }, std::chrono::seconds(5)));
  pusher.stop();
  EXPECT_EQ(hub.accepted(), std::vector<std::int64_t>{b});
  EXPECT_EQ(hub.attempts(a), 0);  // the item's push never went without its image
  EXPECT_EQ(hub.blobPuts.load(), 1);
  const auto refused =
      station.read<std::vector<RefusedOutboxEntry>>([](Catalog& c) { return c.refusedOutbox(); });
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].row.itemId, a);
  EXPECT_EQ(refused[0].httpStatus, 413);
  EXPECT_NE(refused[0].reason.find("PUT /api/hub/blobs/" + sha), std::string::npos)
      << refused[0].reason;
}

TEST(HubPusher, AWrongTokenParksNothingAndIsReported) {
  test::TempDir dir;
  CatalogOnlyStation station(dir.path());
  station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("A")); });
  ScriptedHub hub;
  hub.tokenStatus = 401;
  HubPusher pusher(station, pusherConfig(hub));
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return !pusher.tokenRefused().empty(); }, std::chrono::seconds(5)));
  pusher.stop();
  EXPECT_NE(pusher.tokenRefused().find("401"), std::string::npos) << pusher.tokenRefused();
  EXPECT_EQ(pusher.status()["token_refused"].get<std::string>(), pusher.tokenRefused());
  EXPECT_EQ(station.read<std::int64_t>([](Catalog& c) { return c.outboxSize(); }), 1);
  EXPECT_EQ(station.read<std::int64_t>([](Catalog& c) { return c.refusedOutboxSize(); }), 0);
  EXPECT_TRUE(hub.accepted().empty());
}

// --- over TLS: throwaway certificates (common/test_certs.h) -------------------------------------

TEST(HubPusher, PushesOverTlsToAHubItsCaVouchesFor) {
  test::TempDir dir;
  const garmcap::test::TestCerts certs(dir.path() / "tls");
  CatalogOnlyStation station(dir.path());
  const auto id = station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("A")); });
  ScriptedHub hub(makeServerTlsContext(certs.serverCert, certs.serverKey));
  Config c = pusherConfig(hub);
  ASSERT_EQ(c.hubUrl.rfind("https://", 0), 0u);
  c.hubCaFile = certs.caCert;
  HubPusher pusher(station, c);
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return hub.accepted().size() == 1; }, std::chrono::seconds(5)))
      << pusher.tlsFailed();
  ASSERT_TRUE(waitFor(
      [&] { return station.read<std::int64_t>([](Catalog& c) { return c.outboxSize(); }) == 0; },
      std::chrono::seconds(5)));
  pusher.stop();
  EXPECT_EQ(hub.accepted(), std::vector<std::int64_t>{id});
  EXPECT_TRUE(pusher.status()["tls_error"].is_null());
  EXPECT_EQ(pusher.status()["url"], hub.url());
}

// The hub is reachable, but its certificate is not vouched for (another CA) or names another
// host: nothing is sent, nothing is parked, the pusher retries with its backoff and says why.
TEST(HubPusher, AHubCertificateFromAnotherCaIsRefusedRetriedAndReported) {
  test::TempDir dir;
  const garmcap::test::TestCerts certs(dir.path() / "tls");
  CatalogOnlyStation station(dir.path());
  station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("A")); });
  ScriptedHub hub(makeServerTlsContext(certs.serverCert, certs.serverKey));
  Config c = pusherConfig(hub);
  c.hubCaFile = certs.otherCaCert;
  HubPusher pusher(station, c);
  pusher.start();
  // The first try fails at once, the second 0.5 s later (hubBackoff).
  ASSERT_TRUE(
      waitFor([&] { return pusher.counters().failures.load() >= 2; }, std::chrono::seconds(5)));
  pusher.stop();
  const std::string why = pusher.tlsFailed();
  EXPECT_NE(why.find("unable to get local issuer certificate"), std::string::npos) << why;
  EXPECT_NE(why.find(hub.url()), std::string::npos) << why;
  EXPECT_EQ(pusher.status()["tls_error"].get<std::string>(), why);
  EXPECT_TRUE(hub.accepted().empty());
  EXPECT_EQ(station.read<std::int64_t>([](Catalog& c) { return c.outboxSize(); }), 1);
  EXPECT_EQ(station.read<std::int64_t>([](Catalog& c) { return c.refusedOutboxSize(); }), 0);
  EXPECT_TRUE(pusher.tokenRefused().empty());
}

TEST(HubPusher, AHubCertificateForAnotherHostNameIsRefused) {
  test::TempDir dir;
  const garmcap::test::TestCerts certs(dir.path() / "tls");
  CatalogOnlyStation station(dir.path());
  station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("A")); });
  ScriptedHub hub(makeServerTlsContext(certs.serverCert, certs.serverKey));
  Config c = pusherConfig(hub);
  c.hubUrl = hub.url("localhost");  // the certificate names 127.0.0.1 and hub.test only
  c.hubCaFile = certs.caCert;
  HubPusher pusher(station, c);
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return !pusher.tlsFailed().empty(); }, std::chrono::seconds(5)));
  pusher.stop();
  EXPECT_NE(pusher.tlsFailed().find("certificate is not for localhost"), std::string::npos)
      << pusher.tlsFailed();
  EXPECT_TRUE(hub.accepted().empty());
  EXPECT_EQ(station.read<std::int64_t>([](Catalog& c) { return c.outboxSize(); }), 1);
}

// A hub that speaks plain HTTP where the station expects TLS: a handshake failure, reported.
TEST(HubPusher, APlainHttpHubAtAnHttpsUrlIsReportedAsATlsFailure) {
  test::TempDir dir;
  const garmcap::test::TestCerts certs(dir.path() / "tls");
  CatalogOnlyStation station(dir.path());
  station.read<std::int64_t>([](Catalog& c) { return c.addItem(plainItem("A")); });
  ScriptedHub hub;
  Config c = pusherConfig(hub);
  c.hubUrl = "https://" + c.hubUrl.substr(7);
  c.hubCaFile = certs.caCert;
  HubPusher pusher(station, c);
  pusher.start();
  ASSERT_TRUE(waitFor([&] { return !pusher.tlsFailed().empty(); }, std::chrono::seconds(5)));
  pusher.stop();
  EXPECT_NE(pusher.tlsFailed().find("TLS with " + c.hubUrl + " failed"), std::string::npos)
      << pusher.tlsFailed();
  EXPECT_TRUE(hub.accepted().empty());
}

TEST(HubPusher, ACaFileWithoutACertificateStopsTheStart) {
  test::TempDir dir;
  CatalogOnlyStation station(dir.path());
  const auto ca = dir.path() / "ca.pem";
  std::ofstream(ca) << "this is not PEM\n";
  Config c;
  c.hubUrl = "https://127.0.0.1:1";
  c.hubToken = "t";
  c.hubCaFile = ca.string();
  try {
    HubPusher pusher(station, c);
    FAIL() << "a CA file without a certificate must be refused";
  } catch (const TlsError& e) {
    EXPECT_NE(std::string(e.what()).find("CA file " + ca.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::daemon
