// The hub's HTTP API in process (HubService on a loopback port, a real PostgreSQL): who may call
// what, the blob hash check, the push and patch answers, and the station's request guard.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <vector>

#include "../e2e/daemon_harness.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/hub/hub_service.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

using e2e::Json;
using e2e::Reply;
namespace http = e2e::http;

class HubHttpTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::postgresBinDir())
      return;
    pg_ = new test::TempPostgres();
    pg_->createDatabase("hub_http");
    HubConfig c;
    c.databaseUrl = pg_->url("hub_http");
    c.listenPort = 0;
    c.adminTokenSha256 = tokenHash("admin-secret");
    c.stationTokenSha256 = {{"shop1", tokenHash("shop1-secret")},
                            {"shop2", tokenHash("shop2-secret")}};
    service_ = new HubService(c);
    service_->start();
  }
  static void TearDownTestSuite() {
    delete service_;
    delete pg_;
    service_ = nullptr;
    pg_ = nullptr;
  }
  void SetUp() override {
    if (!pg_)
      GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql "
                      "(apt install postgresql-15; ./station.sh deps installs it)";
  }
  static Reply call(http::verb verb, const std::string& target, const std::string& token,
                    const std::string& body = "", const std::string& type = "application/json",
                    const std::string& host = "127.0.0.1") {
    std::vector<std::pair<std::string, std::string>> fields = {{"Host", host}};
    if (!token.empty())
      fields.emplace_back("Authorization", "Bearer " + token);
    if (!body.empty())
      fields.emplace_back("Content-Type", type);
    return e2e::httpCallWith(service_->port(), verb, target, fields, body);
  }
  static std::string pushBody(std::int64_t localId, const std::string& sha,
                              const std::string& status = "needs_review") {
    Json item{{"sku", "S" + std::to_string(localId)},
              {"title", "T" + std::to_string(localId)},
              {"status", status},
              {"type", "skirt"},
              {"measurements", {{"waist_circ", 70.0}}},
              {"images", Json::object()}};
    if (!sha.empty())
      item["images"]["dressed"] = {{"sha256", sha}, {"media_type", "image/png"}};
    return Json{{"local_id", localId}, {"item", item}, {"deleted", false}}.dump();
  }

  static test::TempPostgres* pg_;
  static HubService* service_;
};
test::TempPostgres* HubHttpTest::pg_ = nullptr;
HubService* HubHttpTest::service_ = nullptr;

TEST_F(HubHttpTest, BlobsAreCheckedByTheirHashAndSentByStationsOnly) {
  const std::string bytes = std::string("\x89PNG\r\n\x1a\n", 8) + std::string(5000, '\x07');
  const std::string sha = daemon::sha256Hex(bytes);
  const std::string url = "/api/hub/blobs/" + sha;
  EXPECT_EQ(call(http::verb::head, url, "shop1-secret").status, 404);
  EXPECT_EQ(call(http::verb::put, url, "", bytes, "application/octet-stream").status, 401);
  EXPECT_EQ(call(http::verb::put, url, "admin-secret", bytes, "application/octet-stream").status,
            401);
  // One flipped byte: refused, and nothing stored.
  std::string flipped = bytes;
  flipped[100] ^= 1;
  const auto bad = call(http::verb::put, url, "shop1-secret", flipped, "application/octet-stream");
  EXPECT_EQ(bad.status, 400);
  EXPECT_NE(bad.body.find(daemon::sha256Hex(flipped)), std::string::npos) << bad.body;
  EXPECT_EQ(call(http::verb::head, url, "shop1-secret").status, 404);
  EXPECT_EQ(call(http::verb::put, url, "shop1-secret", bytes, "application/octet-stream").status,
            201);
  EXPECT_EQ(call(http::verb::put, url, "shop2-secret", bytes, "application/octet-stream").status,
            200);
  EXPECT_EQ(call(http::verb::head, url, "shop2-secret").status, 200);
  const auto got = call(http::verb::get, url, "admin-secret");
  ASSERT_EQ(got.status, 200);
  EXPECT_EQ(got.body, bytes);
  EXPECT_EQ(call(http::verb::head, "/api/hub/blobs/ABC", "shop1-secret").status, 400);
  // Raw bytes with another verb are refused by the station's guard.
  EXPECT_EQ(
      call(http::verb::post, "/api/hub/push", "shop1-secret", bytes, "application/octet-stream")
          .status,
      415);
}

TEST_F(HubHttpTest, PushPatchAndChangesFollowTheOwnershipRule) {
  const std::string bytes = "frame-of-item-41";
  const std::string sha = daemon::sha256Hex(bytes);
  EXPECT_EQ(call(http::verb::post, "/api/hub/push", "admin-secret", pushBody(41, sha)).status, 401);
  const auto missing = call(http::verb::post, "/api/hub/push", "shop1-secret", pushBody(41, sha));
  EXPECT_EQ(missing.status, 409);
  EXPECT_NE(missing.body.find(sha), std::string::npos);
  ASSERT_EQ(call(http::verb::put, "/api/hub/blobs/" + sha, "shop1-secret", bytes,
                 "application/octet-stream")
                .status,
            201);
  const auto pushed = call(http::verb::post, "/api/hub/push", "shop1-secret", pushBody(41, sha));
  ASSERT_EQ(pushed.status, 200) << pushed.body;
  EXPECT_TRUE(pushed.json()["created"].get<bool>());
  const auto again = call(http::verb::post, "/api/hub/push", "shop1-secret", pushBody(41, sha));
  EXPECT_EQ(again.json()["id"], pushed.json()["id"]);
  EXPECT_FALSE(again.json()["created"].get<bool>());
  EXPECT_EQ(call(http::verb::post, "/api/hub/push", "shop1-secret", R"({"local_id": 0})").status,
            400);
  EXPECT_EQ(
      call(http::verb::post, "/api/hub/push", "shop1-secret", pushBody(42, "", "sold")).status,
      400);

  const std::string item = "/api/items/" + pushed.json()["id"].dump();
  EXPECT_EQ(call(http::verb::patch, item, "shop1-secret", R"({"title": "x"})").status, 401);
  EXPECT_EQ(call(http::verb::patch, item, "admin-secret", R"({"title": "x"})").status, 409);
  EXPECT_EQ(call(http::verb::patch, item, "admin-secret", R"({"sku": "x"})").status, 400);
  const auto approved = call(http::verb::patch, item, "admin-secret",
                             R"({"status": "approved", "title": "Hub", "price_cents": 990})");
  ASSERT_EQ(approved.status, 200) << approved.body;
  EXPECT_EQ(approved.json()["title"], "Hub");
  EXPECT_TRUE(approved.json()["hub_owned"].get<bool>());
  EXPECT_EQ(approved.json()["images"]["dressed"]["sha256"], sha);

  const auto changes = call(http::verb::get, "/api/hub/changes?since=0", "shop1-secret").json();
  ASSERT_EQ(changes["changes"].size(), 1u) << changes.dump();
  EXPECT_EQ(changes["changes"][0]["local_id"], 41);
  EXPECT_EQ(changes["changes"][0]["price_cents"], 990);
  EXPECT_EQ(call(http::verb::get, "/api/hub/changes?since=0", "shop2-secret").json()["changes"],
            Json::array());
  const auto after =
      call(http::verb::get, "/api/hub/changes?since=" + changes["next"].dump(), "shop1-secret");
  EXPECT_EQ(after.json()["changes"], Json::array());
  EXPECT_EQ(call(http::verb::get, "/api/hub/changes?since=0", "admin-secret").status, 401);
}

TEST_F(HubHttpTest, AStationTokenReadsOnlyItsOwnStationAndTheAdminTokenReadsAll) {
  const auto a = call(http::verb::post, "/api/hub/push", "shop1-secret", pushBody(51, ""));
  ASSERT_EQ(a.status, 200) << a.body;
  const std::string bytes = "frame-of-shop2-item-52";
  const std::string sha = daemon::sha256Hex(bytes);
  ASSERT_EQ(call(http::verb::put, "/api/hub/blobs/" + sha, "shop2-secret", bytes,
                 "application/octet-stream")
                .status,
            201);
  const auto b = call(http::verb::post, "/api/hub/push", "shop2-secret", pushBody(52, sha));
  ASSERT_EQ(b.status, 200) << b.body;
  const std::string itemA = "/api/items/" + a.json()["id"].dump();
  const std::string itemB = "/api/items/" + b.json()["id"].dump();

  // One item: another station's is absent; the own one and the admin's reads are there.
  EXPECT_EQ(call(http::verb::get, itemB, "shop1-secret").status, 404);
  EXPECT_EQ(call(http::verb::get, itemA, "shop2-secret").status, 404);
  EXPECT_EQ(call(http::verb::get, itemA, "shop1-secret").status, 200);
  EXPECT_EQ(call(http::verb::get, itemB, "shop2-secret").status, 200);
  EXPECT_EQ(call(http::verb::get, itemB, "admin-secret").status, 200);

  // Lists: a station token gets its own station's items, and 403 for another's filter.
  EXPECT_EQ(call(http::verb::get, "/api/items?station=shop2", "shop1-secret").status, 403);
  auto stationsIn = [](const Json& page) {
    std::set<std::string> out;
    for (const auto& it : page["items"])
      out.insert(it["station"].get<std::string>());
    return out;
  };
  EXPECT_EQ(stationsIn(call(http::verb::get, "/api/items?limit=500", "shop1-secret").json()),
            std::set<std::string>{"shop1"});
  EXPECT_EQ(stationsIn(call(http::verb::get, "/api/items?station=shop1", "shop1-secret").json()),
            std::set<std::string>{"shop1"});
  EXPECT_EQ(stationsIn(call(http::verb::get, "/api/items?limit=500", "admin-secret").json()),
            (std::set<std::string>{"shop1", "shop2"}));

  // Blobs: only those of the station's own items (HEAD, the pusher's question, stays open).
  const std::string blob = "/api/hub/blobs/" + sha;
  EXPECT_EQ(call(http::verb::get, blob, "shop1-secret").status, 404);
  EXPECT_EQ(call(http::verb::head, blob, "shop1-secret").status, 200);
  EXPECT_EQ(call(http::verb::get, blob, "shop2-secret").body, bytes);
  EXPECT_EQ(call(http::verb::get, blob, "admin-secret").body, bytes);

  // Changes: the hub's edit of shop2's item goes to shop2 only.
  ASSERT_EQ(call(http::verb::patch, itemB, "admin-secret",
                 R"({"status": "approved", "title": "Edited for shop2"})")
                .status,
            200);
  auto titles = [&](const std::string& token) {
    const Json page = call(http::verb::get, "/api/hub/changes?since=0&limit=1000", token).json();
    std::set<std::string> out;
    for (const auto& ch : page["changes"])
      out.insert(ch["title"].get<std::string>());
    return out;
  };
  EXPECT_EQ(titles("shop1-secret").count("Edited for shop2"), 0u);
  EXPECT_EQ(titles("shop2-secret").count("Edited for shop2"), 1u);
}

TEST_F(HubHttpTest, SessionSaysATokenIsRequiredAndWhoTheCallerIs) {
  const auto none = call(http::verb::get, "/api/session", "");
  ASSERT_EQ(none.status, 200) << none.body;
  EXPECT_EQ(none.json()["token_required"], true);
  EXPECT_EQ(none.json()["authenticated"], false);
  EXPECT_EQ(call(http::verb::get, "/api/session", "wrong").json()["authenticated"], false);
  const auto shop = call(http::verb::get, "/api/session", "shop1-secret").json();
  EXPECT_EQ(shop["authenticated"], true);
  EXPECT_EQ(shop["role"], "station");
  EXPECT_EQ(shop["station"], "shop1");
  const auto admin = call(http::verb::get, "/api/session", "admin-secret").json();
  EXPECT_EQ(admin["role"], "admin");
  EXPECT_EQ(admin["station"], nullptr);
  EXPECT_EQ(admin["login"], true);  // a browser may trade its token for a cookie (below)
}

// The web UI's log-in: a token for an HttpOnly cookie that stands for the token's caller, with
// exactly its rights, until DELETE /api/session.
TEST_F(HubHttpTest, ABrowserSessionStandsForTheTokenThatOpenedIt) {
  const auto wrong = call(http::verb::post, "/api/session", "", R"({"token": "guess"})");
  EXPECT_EQ(wrong.status, 401) << wrong.body;
  EXPECT_EQ(call(http::verb::post, "/api/session", "", R"({"tok": "admin-secret"})").status, 400);
  // The guard's rules: JSON only, same origin only.
  EXPECT_EQ(call(http::verb::post, "/api/session", "", R"({"token": "admin-secret"})", "text/plain")
                .status,
            415);
  // POST /api/session with its Set-Cookie (the harness's Reply has no such field).
  struct LogIn {
    int status = 0;
    std::string body, setCookie;
    Json json() const { return Json::parse(body, nullptr, false); }
  };
  auto login = [](const std::string& token, const std::string& origin = "") {
    namespace asio = boost::asio;
    asio::io_context io;
    boost::beast::tcp_stream stream(io);
    stream.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), service_->port()));
    http::request<http::string_body> req{http::verb::post, "/api/session", 11};
    req.set("Host", "127.0.0.1");
    req.set("Content-Type", "application/json");
    if (!origin.empty())
      req.set("Origin", origin);
    req.body() = Json{{"token", token}}.dump();
    req.prepare_payload();
    http::write(stream, req);
    boost::beast::flat_buffer buf;
    http::response<http::string_body> res;
    http::read(stream, buf, res);
    return LogIn{static_cast<int>(res.result_int()), res.body(),
                 std::string(res[http::field::set_cookie])};
  };
  EXPECT_EQ(login("admin-secret", "http://evil.example").status, 403);
  auto cookieOf = [](const LogIn& r) {
    EXPECT_NE(r.setCookie.find("HttpOnly"), std::string::npos) << r.setCookie;
    EXPECT_NE(r.setCookie.find("SameSite=Strict"), std::string::npos) << r.setCookie;
    EXPECT_EQ(r.setCookie.find("Secure"), std::string::npos) << "plain HTTP on loopback";
    return r.setCookie.substr(0, r.setCookie.find(';'));
  };
  const auto admin = login("admin-secret");
  ASSERT_EQ(admin.status, 200) << admin.body;
  EXPECT_EQ(admin.json()["role"], "admin");
  const std::string adminCookie = cookieOf(admin);
  const auto shop = login("shop2-secret");
  ASSERT_EQ(shop.status, 200) << shop.body;
  EXPECT_EQ(shop.json()["station"], "shop2");
  const std::string shopCookie = cookieOf(shop);
  auto withCookie = [](http::verb verb, const std::string& target, const std::string& cookie,
                       const std::string& body = "") {
    std::vector<std::pair<std::string, std::string>> fields = {{"Host", "127.0.0.1"},
                                                               {"Cookie", cookie}};
    if (!body.empty())
      fields.emplace_back("Content-Type", "application/json");
    return e2e::httpCallWith(service_->port(), verb, target, fields, body);
  };
  EXPECT_EQ(withCookie(http::verb::get, "/api/session", adminCookie).json()["role"], "admin");
  EXPECT_EQ(withCookie(http::verb::get, "/api/items", adminCookie).status, 200);
  // The station's cookie: its own station's items and stations only, and no edits.
  EXPECT_EQ(withCookie(http::verb::get, "/api/items?station=shop1", shopCookie).status, 403);
  const auto stations = withCookie(http::verb::get, "/api/hub/stations", shopCookie);
  ASSERT_EQ(stations.status, 200) << stations.body;
  EXPECT_EQ(stations.json()["stations"].size(), 1u);
  EXPECT_EQ(stations.json()["stations"][0]["id"], "shop2");
  const auto all = withCookie(http::verb::get, "/api/hub/stations", adminCookie).json();
  ASSERT_EQ(all["stations"].size(), 2u);
  EXPECT_EQ(all["stations"][0]["id"], "shop1");
  EXPECT_EQ(all["stations"][1]["id"], "shop2");
  EXPECT_EQ(
      withCookie(http::verb::patch, "/api/items/1", shopCookie, R"({"status":"approved"})").status,
      401);
  // A made-up cookie is nobody; a revoked one too.
  EXPECT_EQ(
      withCookie(http::verb::get, "/api/items", "garmcap_session=" + std::string(64, 'a')).status,
      401);
  const auto out = withCookie(http::verb::delete_, "/api/session", adminCookie);
  EXPECT_EQ(out.status, 200);
  EXPECT_EQ(withCookie(http::verb::get, "/api/items", adminCookie).status, 401);
  EXPECT_EQ(withCookie(http::verb::get, "/api/items", shopCookie).status, 200);
  EXPECT_EQ(call(http::verb::get, "/api/hub/stations", "").status, 401);
}

TEST_F(HubHttpTest, ListsValidateTheirQueryAndTheGuardApplies) {
  EXPECT_EQ(call(http::verb::get, "/api/items?status=sold", "admin-secret").status, 400);
  EXPECT_EQ(call(http::verb::get, "/api/items?status=approved", "admin-secret").status, 200);
  EXPECT_EQ(call(http::verb::get, "/api/items", "").status, 401);
  EXPECT_EQ(call(http::verb::get, "/api/items", "wrong").status, 401);
  EXPECT_EQ(call(http::verb::get, "/api/items?limit=0", "admin-secret").status, 400);
  EXPECT_EQ(call(http::verb::get, "/api/items?after=abc", "admin-secret").status, 400);
  EXPECT_EQ(call(http::verb::get, "/api/items?station=a%2Fb", "admin-secret").status, 400);
  EXPECT_EQ(call(http::verb::get, "/api/items?limit=5", "admin-secret").status, 200);
  EXPECT_EQ(call(http::verb::get, "/api/items/999999", "admin-secret").status, 404);
  // DNS rebinding: a name that is not the hub's is refused before any route.
  EXPECT_EQ(call(http::verb::get, "/api/items", "admin-secret", "", "", "evil.example:8090").status,
            403);
  const auto health = call(http::verb::get, "/api/hub/health", "").json();
  EXPECT_EQ(health["schema"], kHubSchemaVersion);
}

// The chain's Shopify CSV, read back by Python's csv module in strict mode (an independent
// RFC 4180 reader; it refuses a stray quote or an unterminated field): the approved items of
// both stations are there once each, the same local id at two stations being two products;
// an item waiting for review and a deleted one are not; the header is the station writer's;
// a title with a quote, a comma and a line break comes back as it went in; the image link
// names the hub's item and the hub serves it; `station=` and a station token narrow it.
std::vector<std::vector<std::string>> strictCsvRows(const std::string& csv) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("hub-export-" + std::to_string(::getpid()) + ".csv");
  std::ofstream(file, std::ios::binary) << csv;
  const std::string cmd =
      "python3 -c 'import csv, json, sys\n"
      "rows = list(csv.reader(open(sys.argv[1], newline=\"\", encoding=\"utf-8\"), strict=True))\n"
      "assert all(len(r) == len(rows[0]) for r in rows), \"ragged rows\"\n"
      "print(json.dumps(rows))' " +
      file.string() + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  for (std::size_t n; p && (n = std::fread(buf, 1, sizeof buf, p)) > 0;)
    out.append(buf, n);
  const int rc = p ? ::pclose(p) : -1;
  std::filesystem::remove(file);
  if (rc != 0)
    throw std::runtime_error("python3 csv (strict) refused the file: " + out);
  return Json::parse(out).get<std::vector<std::vector<std::string>>>();
}

TEST_F(HubHttpTest, TheChainsShopifyCsvHoldsTheApprovedItemsOfEveryStationOnce) {
  const std::string jpeg = std::string("\xff\xd8\xff\xe0", 4) + std::string(300, '\x11');
  const std::string sha = daemon::sha256Hex(jpeg);
  ASSERT_EQ(call(http::verb::put, "/api/hub/blobs/" + sha, "shop1-secret", jpeg,
                 "application/octet-stream")
                .status,
            201);
  const std::string trickyTitle = "Navy \"A-line\" skirt, pleated\r\nsecond line";
  auto push = [](const std::string& token, std::int64_t localId, const std::string& sku,
                 const std::string& title, const std::string& status, bool deleted,
                 const Json& images) {
    Json item{{"sku", sku},
              {"title", title},
              {"status", status},
              {"type", "skirt"},
              {"price_cents", 4900},
              {"notes", "Wool, lined."},
              {"tags", {"autumn"}},
              {"attributes", {{"color", "navy"}}},
              {"measurements", {{"waist_circ", 70.0}, {"garment_length", 62.5}}},
              {"images", images}};
    const auto r = call(http::verb::post, "/api/hub/push", token,
                        Json{{"local_id", localId}, {"item", item}, {"deleted", deleted}}.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    return r.json()["id"].get<std::int64_t>();
  };
  const Json product{{"product", {{"sha256", sha}, {"media_type", "image/jpeg"}}}};
  const auto a = push("shop1-secret", 901, "EXP-A-901", trickyTitle, "approved", false, product);
  push("shop1-secret", 902, "EXP-A-902", "Waiting", "needs_review", false, Json::object());
  push("shop1-secret", 903, "EXP-A-903", "Gone", "approved", true, Json::object());
  push("shop2-secret", 901, "EXP-B-901", "Cream blouse", "approved", false, Json::object());

  const std::string options =
      "base_url=https://files.shop.test/hub&store_url=https://shop.test&brand=Chain";
  const auto res =
      call(http::verb::get, "/api/export/shopify.csv?" + options, "admin-secret", "", "");
  ASSERT_EQ(res.status, 200) << res.body;
  EXPECT_EQ(res.contentType, "text/csv; charset=utf-8");
  EXPECT_NE(res.disposition.find("shopify.csv"), std::string::npos);
  const auto rows = strictCsvRows(res.body);
  ASSERT_GE(rows.size(), 3u);
  const auto& header = rows[0];
  // The station's writer, same options: the same columns.
  daemon::ShopOptions o;
  o.publicBaseUrl = "https://files.shop.test/hub";
  o.storeUrl = "https://shop.test";
  o.brand = "Chain";
  EXPECT_EQ(res.body.substr(0, res.body.find("\r\n")),
            daemon::shopifyCsv({}, o).bytes.substr(0, res.body.find("\r\n")));
  auto column = [&](const std::string& name) {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << name;
    return static_cast<std::size_t>(at - header.begin());
  };
  const std::size_t sku = column("SKU"), title = column("Title"),
                    image = column("Product image URL"), vendor = column("Vendor");
  std::map<std::string, int> skus;
  std::map<std::string, std::vector<std::string>> bySku;
  for (std::size_t i = 1; i < rows.size(); ++i)
    if (rows[i][sku].rfind("EXP-", 0) == 0) {
      ++skus[rows[i][sku]];
      bySku[rows[i][sku]] = rows[i];
    }
  EXPECT_EQ(skus, (std::map<std::string, int>{{"EXP-A-901", 1}, {"EXP-B-901", 1}}));
  EXPECT_EQ(bySku["EXP-A-901"][title], trickyTitle);
  EXPECT_EQ(bySku["EXP-B-901"][title], "Cream blouse");
  EXPECT_EQ(bySku["EXP-A-901"][vendor], "Chain");
  const std::string imagePath = "images/" + std::to_string(a) + "-product.jpg";
  EXPECT_EQ(bySku["EXP-A-901"][image], "https://files.shop.test/hub/" + imagePath);
  const auto served = call(http::verb::get, "/api/export/files/" + imagePath, "admin-secret");
  EXPECT_EQ(served.status, 200);
  EXPECT_EQ(served.body, jpeg);
  EXPECT_EQ(call(http::verb::get, "/api/export/files/" + imagePath, "shop2-secret").status, 404);

  // One station: by the admin's filter or by a station's own token.
  auto skusOf = [&](const std::string& query, const std::string& token) {
    std::set<std::string> out;
    const auto r = call(http::verb::get, "/api/export/shopify.csv?" + query, token, "", "");
    EXPECT_EQ(r.status, 200) << r.body;
    const auto rs = strictCsvRows(r.body);
    for (std::size_t i = 1; i < rs.size(); ++i)
      if (rs[i][sku].rfind("EXP-", 0) == 0)
        out.insert(rs[i][sku]);
    return out;
  };
  EXPECT_EQ(skusOf(options + "&station=shop2", "admin-secret"), std::set<std::string>{"EXP-B-901"});
  EXPECT_EQ(skusOf(options, "shop1-secret"), std::set<std::string>{"EXP-A-901"});
  EXPECT_EQ(
      call(http::verb::get, "/api/export/shopify.csv?" + options + "&station=shop2", "shop1-secret")
          .status,
      403);
  EXPECT_EQ(call(http::verb::get, "/api/export/shopify.csv?" + options, "").status, 401);
  // The station's rules: no public base URL, no export (422 naming the option).
  const auto noBase = call(http::verb::get, "/api/export/shopify.csv", "admin-secret");
  EXPECT_EQ(noBase.status, 422);
  EXPECT_NE(noBase.body.find("base"), std::string::npos) << noBase.body;
}

// The review UI's export page downloads through the session cookie (a link cannot carry an
// Authorization header): the export routes take the cookie with the rights of the token that
// opened it, as the list and item routes do. An admin's cookie exports every station (or the
// `station=` one); a station's cookie exports its own items only, 403 for another station's.
TEST_F(HubHttpTest, ExportsTakeTheSessionCookieWithTheRightsOfItsToken) {
  auto cookieFor = [](const std::string& token) {
    namespace asio = boost::asio;
    asio::io_context io;
    boost::beast::tcp_stream stream(io);
    stream.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), service_->port()));
    http::request<http::string_body> req{http::verb::post, "/api/session", 11};
    req.set("Host", "127.0.0.1");
    req.set("Content-Type", "application/json");
    req.body() = Json{{"token", token}}.dump();
    req.prepare_payload();
    http::write(stream, req);
    boost::beast::flat_buffer buf;
    http::response<http::string_body> res;
    http::read(stream, buf, res);
    EXPECT_EQ(res.result_int(), 200u) << res.body();
    const std::string set = std::string(res[http::field::set_cookie]);
    return set.substr(0, set.find(';'));
  };
  auto get = [](const std::string& target, const std::string& cookie) {
    return e2e::httpCallWith(service_->port(), http::verb::get, target,
                             {{"Host", "127.0.0.1"}, {"Cookie", cookie}}, "");
  };
  auto push = [](const std::string& token, std::int64_t localId, const std::string& sku) {
    const Json item{{"sku", sku},    {"title", "Cookie " + sku}, {"status", "approved"},
                    {"type", "top"}, {"price_cents", 1500},      {"images", Json::object()}};
    const auto r = call(http::verb::post, "/api/hub/push", token,
                        Json{{"local_id", localId}, {"item", item}, {"deleted", false}}.dump());
    EXPECT_EQ(r.status, 200) << r.body;
  };
  push("shop1-secret", 951, "CK-A-951");
  push("shop2-secret", 951, "CK-B-951");
  const std::string admin = cookieFor("admin-secret"), shop2 = cookieFor("shop2-secret");
  ASSERT_FALSE(admin.empty());
  ASSERT_FALSE(shop2.empty());
  const std::string options =
      "base_url=https://files.shop.test/hub&store_url=https://shop.test&brand=Chain";
  auto cookieSkus = [&](const std::string& file, const std::string& query,
                        const std::string& cookie) {
    std::set<std::string> out;
    const auto r = get("/api/export/" + file + "?" + query, cookie);
    EXPECT_EQ(r.status, 200) << file << " " << query << ": " << r.body;
    if (r.status != 200)
      return out;
    for (const std::string sku : {"CK-A-951", "CK-B-951"})
      if (r.body.find(sku) != std::string::npos)
        out.insert(sku);
    return out;
  };
  for (const std::string file : {"shopify.csv", "woocommerce.csv", "merchant.tsv"}) {
    SCOPED_TRACE(file);
    EXPECT_EQ(cookieSkus(file, options, admin), (std::set<std::string>{"CK-A-951", "CK-B-951"}));
    EXPECT_EQ(cookieSkus(file, options + "&station=shop1", admin),
              std::set<std::string>{"CK-A-951"});
    EXPECT_EQ(cookieSkus(file, options, shop2), std::set<std::string>{"CK-B-951"});
    EXPECT_EQ(get("/api/export/" + file + "?" + options + "&station=shop1", shop2).status, 403);
    EXPECT_EQ(get("/api/export/" + file + "?" + options, "garmcap_session=" + std::string(64, 'b'))
                  .status,
              401);
  }
  const auto zip = get("/api/export/catalog.zip?" + options + "&station=shop2", shop2);
  EXPECT_EQ(zip.status, 200) << zip.body;
  EXPECT_EQ(zip.body.substr(0, 2), "PK");
  EXPECT_EQ(get("/api/export/catalog.zip?" + options + "&station=shop1", shop2).status, 403);
  EXPECT_EQ(get("/api/export/catalog.zip?" + options, "").status, 401);
  // The export page's counts: each station's live items by status, equal to the list's.
  const auto stations = get("/api/hub/stations", admin);
  ASSERT_EQ(stations.status, 200) << stations.body;
  // The parsed body is kept: a range-for over a member of the temporary json() would read it
  // after it is destroyed (ASan: heap-use-after-free).
  const Json stationList = stations.json()["stations"];
  for (const auto& st : stationList)
    for (const std::string status : {"needs_review", "approved", "rejected"}) {
      std::size_t listed = 0;
      for (Json next = 0;;) {
        const auto page = call(http::verb::get,
                               "/api/items?limit=500&station=" + st["id"].get<std::string>() +
                                   "&status=" + status +
                                   (next.is_number() && next != 0 ? "&after=" + next.dump() : ""),
                               "admin-secret");
        ASSERT_EQ(page.status, 200) << page.body;
        listed += page.json()["items"].size();
        next = page.json()["next"];
        if (next.is_null())
          break;
      }
      EXPECT_EQ(st["statuses"][status].get<std::size_t>(), listed) << st.dump() << " " << status;
    }
  // Logged out, the cookie exports nothing.
  e2e::httpCallWith(service_->port(), http::verb::delete_, "/api/session",
                    {{"Host", "127.0.0.1"}, {"Cookie", shop2}}, "");
  EXPECT_EQ(get("/api/export/shopify.csv?" + options, shop2).status, 401);
}

}  // namespace
}  // namespace garmcap::hub
