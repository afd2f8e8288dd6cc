// Patterns at the hub (a real PostgreSQL, HubService on a loopback port): the patterns a station
// pushes with its items are stored and served as pattern.json, pattern.svg, pattern.dxf and
// pattern.pdf for any station's item, and the chain's catalog.zip holds every station's photos,
// pattern files and shop files. Each file is read back by an independent reader: Python's xml
// and zipfile, ezdxf's audit (Debian's python3-ezdxf), poppler's pdfinfo.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include "../common/run_command.h"
#include "../e2e/daemon_harness.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/hub/hub_exports.h"
#include "garmcap/hub/hub_service.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

using garmcap::testing::runCommand;

using e2e::Json;
using e2e::Reply;
namespace http = e2e::http;
namespace fs = std::filesystem;

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

Json readJson(const fs::path& p) {
  std::ifstream in(p);
  return Json::parse(in);
}

class HubPatternTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::postgresBinDir())
      return;
    pg_ = new test::TempPostgres();
    pg_->createDatabase("hub_patterns");
    HubConfig c;
    c.databaseUrl = pg_->url("hub_patterns");
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
      GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql";
    dir_ = fs::temp_directory_path() / ("garmcap-hubpat-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static Reply call(http::verb verb, const std::string& target, const std::string& token,
                    const std::string& body = "", const std::string& type = "application/json") {
    std::vector<std::pair<std::string, std::string>> fields = {{"Host", "127.0.0.1"}};
    if (!token.empty())
      fields.emplace_back("Authorization", "Bearer " + token);
    if (!body.empty())
      fields.emplace_back("Content-Type", type);
    return e2e::httpCallWith(service_->port(), verb, target, fields, body);
  }
  // Pushes an approved item with a photo; `patterns` null leaves the key out of the push.
  static std::int64_t push(const std::string& station, std::int64_t localId, const std::string& sku,
                           const Json& patterns) {
    const std::string photo = "jpeg of " + station + " " + std::to_string(localId);
    const std::string sha = daemon::sha256Hex(photo);
    const auto put = call(http::verb::put, "/api/hub/blobs/" + sha, station + "-secret", photo,
                          "application/octet-stream");
    EXPECT_TRUE(put.status == 200 || put.status == 201) << put.body;
    Json item{{"sku", sku},
              {"title", "Dress " + sku},
              {"status", "approved"},
              {"type", "dress"},
              {"price_cents", 4900},
              {"base_size", "55"},
              {"measurements", {{"bust_circ", 88.0}}},
              {"images", {{"product", {{"sha256", sha}, {"media_type", "image/jpeg"}}}}}};
    Json body{{"local_id", localId}, {"item", item}, {"deleted", false}};
    if (!patterns.is_null())
      body["patterns"] = patterns;
    const auto r = call(http::verb::post, "/api/hub/push", station + "-secret", body.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    return Json::parse(r.body).at("id").get<std::int64_t>();
  }
  fs::path save(const std::string& name, const std::string& bytes) const {
    const auto p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

  static test::TempPostgres* pg_;
  static HubService* service_;
  fs::path dir_;
};
test::TempPostgres* HubPatternTest::pg_ = nullptr;
HubService* HubPatternTest::service_ = nullptr;

const fs::path kDress = fs::path(GARMCAP_TEST_DATA_DIR) / "designs" / "dress_55.json";

TEST_F(HubPatternTest, PatternFilesOfAnyStationsItemAreServedAndReadBackByIndependentReaders) {
  const Json dress = readJson(kDress);
  const auto panels = dress.at("panels").size();
  ASSERT_GT(panels, 1u);
  const std::int64_t a = push("shop1", 11, "P1-11", Json{{"base", dress}});
  const std::int64_t old = push("shop1", 12, "P1-12", nullptr);  // a station that sends none
  const std::int64_t b = push("shop2", 11, "P2-11", Json{{"base", dress}, {"55", dress}});

  auto sizes =
      call(http::verb::get, "/api/items/" + std::to_string(b) + "/patterns", "admin-secret");
  ASSERT_EQ(sizes.status, 200) << sizes.body;
  EXPECT_EQ(Json::parse(sizes.body)["sizes"], Json::array({"55", "base"}));
  // A station reads its own items' patterns only; another's is absent.
  EXPECT_EQ(
      call(http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.json", "shop2-secret")
          .status,
      200);
  EXPECT_EQ(
      call(http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.json", "shop1-secret")
          .status,
      404);
  EXPECT_EQ(call(http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.svg", "").status,
            401);

  const auto json =
      call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.json", "admin-secret");
  ASSERT_EQ(json.status, 200) << json.body;
  EXPECT_EQ(Json::parse(json.body), dress);

  // SVG: well-formed XML (Python's parser), one outline per piece at least.
  const auto svg =
      call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.svg?size=base",
           "shop1-secret");
  ASSERT_EQ(svg.status, 200) << svg.body;
  int st = 0;
  const std::string svgOut = runCommand(
      "/usr/bin/python3 -c 'import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1])"
      ".getroot(); print(r.tag.split(\"}\")[-1], sum(1 for e in r.iter() if e.tag.split(\"}\")"
      "[-1] in (\"path\", \"polygon\", \"polyline\")))' " +
          quoted(save("a.svg", svg.body)) + " 2>&1",
      st);
  ASSERT_EQ(st, 0) << svgOut;
  std::istringstream svgWords(svgOut);
  std::string root;
  std::size_t shapes = 0;
  svgWords >> root >> shapes;
  EXPECT_EQ(root, "svg") << svgOut;
  EXPECT_GE(shapes, panels) << svgOut;

  // DXF-AAMA: ezdxf reads it, audits it clean, and finds one block per piece.
  const auto dxf = call(http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.dxf?size=55",
                        "admin-secret");
  ASSERT_EQ(dxf.status, 200) << dxf.body;
  EXPECT_NE(dxf.disposition.find("P2-11_55.dxf"), std::string::npos) << dxf.disposition;
  const std::string dxfOut = runCommand(
      "/usr/bin/python3 -c 'import sys, ezdxf; d = ezdxf.readfile(sys.argv[1]); a = d.audit(); "
      "print(len(d.modelspace().query(\"INSERT\")), len(a.errors))' " +
          quoted(save("b.dxf", dxf.body)) + " 2>&1",
      st);
  ASSERT_EQ(st, 0) << dxfOut;
  std::istringstream dxfWords(dxfOut);
  std::size_t inserts = 0, errors = 1;
  dxfWords >> inserts >> errors;
  EXPECT_EQ(inserts, panels) << dxfOut;
  EXPECT_EQ(errors, 0u) << dxfOut;

  // PDF: poppler reads it; A0 is one page of A0.
  for (const std::string& paper : {std::string("a4"), std::string("a0")}) {
    const auto pdf =
        call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.pdf?paper=" + paper,
             "admin-secret");
    ASSERT_EQ(pdf.status, 200) << pdf.body;
    const std::string info = runCommand("pdfinfo " + quoted(save("a.pdf", pdf.body)) + " 2>&1", st);
    ASSERT_EQ(st, 0) << info;
    EXPECT_NE(info.find("Pages:"), std::string::npos) << info;
    if (paper == "a0") {
      EXPECT_NE(info.find("(A0)"), std::string::npos) << info;
    }
  }
  EXPECT_EQ(call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.pdf?paper=b5",
                 "admin-secret")
                .status,
            400);

  // Sizes it lacks, items that sent none.
  const auto missing = call(
      http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.dxf?size=66", "admin-secret");
  EXPECT_EQ(missing.status, 404);
  EXPECT_NE(missing.body.find("sizes: 55, base"), std::string::npos) << missing.body;
  const auto none =
      call(http::verb::get, "/api/items/" + std::to_string(old) + "/pattern.svg", "admin-secret");
  EXPECT_EQ(none.status, 404);
  EXPECT_NE(none.body.find("sent no pattern"), std::string::npos) << none.body;

  // A push without "patterns" keeps them; an empty object clears them; a bad one is a 400.
  push("shop1", 11, "P1-11", nullptr);
  EXPECT_EQ(
      call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.json", "admin-secret")
          .status,
      200);
  push("shop1", 11, "P1-11", Json::object());
  EXPECT_EQ(
      call(http::verb::get, "/api/items/" + std::to_string(a) + "/pattern.json", "admin-secret")
          .status,
      404);
  const Json bad{
      {"local_id", 11}, {"item", {{"status", "approved"}}}, {"patterns", {{"../x", dress}}}};
  EXPECT_EQ(call(http::verb::post, "/api/hub/push", "shop1-secret", bad.dump()).status, 400);
  push("shop1", 11, "P1-11", Json{{"base", dress}});
}

// The names in a ZIP as Python's zipfile reads them, after its CRC check of every member.
std::set<std::string> zipNames(const fs::path& file) {
  int st = 0;
  const std::string out = runCommand(
      "/usr/bin/python3 -c 'import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); "
      "bad = z.testzip(); print(\"BAD\", bad) if bad else None; [print(n) for n in "
      "z.namelist()]' " +
          quoted(file) + " 2>&1",
      st);
  if (st != 0 || out.rfind("BAD", 0) == 0)
    throw std::runtime_error("python3 zipfile refused " + file.string() + ": " + out);
  std::set<std::string> names;
  std::istringstream lines(out);
  for (std::string l; std::getline(lines, l);)
    names.insert(l);
  return names;
}

TEST_F(HubPatternTest, TheChainsCatalogZipHoldsEveryStationsPatternsPhotosAndShopFiles) {
  const Json dress = readJson(kDress);
  const std::int64_t a = push("shop1", 21, "Z1-21", Json{{"base", dress}});
  const std::int64_t b = push("shop2", 21, "Z2-21", Json{{"base", dress}, {"55", dress}});
  const std::string query =
      "/api/export/catalog.zip?base_url=https://files.example/chain&brand=Chain"
      "&store_url=https://shop.example";

  const auto all = call(http::verb::get, query, "admin-secret");
  ASSERT_EQ(all.status, 200) << all.body;
  const auto names = zipNames(save("all.zip", all.body));
  for (const std::string& n :
       {"patterns/" + std::to_string(a) + "/base.dxf",
        "patterns/" + std::to_string(a) + "/base.svg",
        "patterns/" + std::to_string(a) + "/garmentcode.json",
        "patterns/" + std::to_string(b) + "/55.dxf", "patterns/" + std::to_string(b) + "/base.dxf",
        "images/" + std::to_string(a) + "-product.jpg",
        "images/" + std::to_string(b) + "-product.jpg", std::string("shopify.csv"),
        std::string("woocommerce.csv"), std::string("merchant.tsv"), std::string("README.txt")})
    EXPECT_EQ(names.count(n), 1u) << n;

  // One station's, by the admin's filter or by its own token; not another's.
  const auto one = call(http::verb::get, query + "&station=shop2", "admin-secret");
  ASSERT_EQ(one.status, 200) << one.body;
  const auto names2 = zipNames(save("shop2.zip", one.body));
  EXPECT_EQ(names2.count("patterns/" + std::to_string(b) + "/55.dxf"), 1u);
  EXPECT_EQ(names2.count("patterns/" + std::to_string(a) + "/base.dxf"), 0u);
  for (const auto& n : names2)
    EXPECT_EQ(n.find("images/" + std::to_string(a) + "-"), std::string::npos) << n;
  const auto own = call(http::verb::get, query, "shop2-secret");
  ASSERT_EQ(own.status, 200);
  EXPECT_EQ(zipNames(save("own.zip", own.body)), names2);
  EXPECT_EQ(call(http::verb::get, query + "&station=shop1", "shop2-secret").status, 403);
  EXPECT_EQ(call(http::verb::get, query, "").status, 401);

  // The DXF inside is the one pattern.dxf serves, and ezdxf audits it clean.
  int st = 0;
  const std::string out = runCommand(
      "cd " + quoted(dir_) +
          " && /usr/bin/python3 -c 'import sys, zipfile, ezdxf, io; "
          "z = zipfile.ZipFile(\"all.zip\"); d = ezdxf.read(io.StringIO(z.read(sys.argv[1])"
          ".decode(\"cp1252\"))); print(len(d.audit().errors))' patterns/" +
          std::to_string(b) + "/55.dxf 2>&1",
      st);
  EXPECT_EQ(st, 0) << out;
  EXPECT_EQ(out, "0\n") << out;
  const auto served = call(
      http::verb::get, "/api/items/" + std::to_string(b) + "/pattern.dxf?size=55", "admin-secret");
  save("served.dxf", served.body);
  const std::string same = runCommand(
      "cd " + quoted(dir_) +
          " && /usr/bin/python3 -c 'import sys, zipfile; z = zipfile.ZipFile(\"all.zip\"); "
          "print(z.read(sys.argv[1]) == open(\"served.dxf\", \"rb\").read())' patterns/" +
          std::to_string(b) + "/55.dxf 2>&1",
      st);
  EXPECT_EQ(same, "True\n") << same;
}

// A CSV or TSV read back by Python's csv module (strict, every row as long as the header).
std::vector<std::vector<std::string>> csvRows(const fs::path& file, char delimiter) {
  int st = 0;
  const std::string out =
      runCommand(std::string("/usr/bin/python3 -c 'import csv, json, sys\n") +
                     "rows = list(csv.reader(open(sys.argv[1], newline=\"\", encoding=\"utf-8\"), "
                     "delimiter=sys.argv[2], strict=True))\n"
                     "assert all(len(r) == len(rows[0]) for r in rows), \"ragged rows\"\n"
                     "print(json.dumps(rows))' " +
                     quoted(file) + " '" +
                     (delimiter == '\t' ? std::string("\t") : std::string(",")) + "' 2>&1",
                 st);
  if (st != 0)
    throw std::runtime_error("python3 csv (strict) refused " + file.string() + ": " + out);
  return Json::parse(out).get<std::vector<std::vector<std::string>>>();
}

std::size_t columnOf(const std::vector<std::string>& header, const std::string& name) {
  const auto at = std::find(header.begin(), header.end(), name);
  if (at == header.end())
    throw std::runtime_error("no column " + name);
  return static_cast<std::size_t>(at - header.begin());
}

// The chain's shop files are written in pages of 500 items from one snapshot (the hub holds a
// page, not the file): 1,234 items give one header and every item once, in id order, and a
// measurement that only the last page's items have still gets its WooCommerce column.
TEST_F(HubPatternTest, TheChainsShopFilesAreWrittenInPagesAndHoldEveryItemOnce) {
  const int n = 1234;
  pg_->psql("hub_patterns",
            "INSERT INTO items(station_id, local_id, sku, title, price_cents, status, type, "
            "hub_owned) SELECT 'shop2', 100000 + g, 'BULK-' || g, 'Bulk skirt ' || g, 1000 + g, "
            "'approved', 'skirt', true FROM generate_series(1, " +
                std::to_string(n) + ") g");
  pg_->psql("hub_patterns",
            "INSERT INTO measurements(item_id, name, value_cm) SELECT id, 'waist_circ', 70 FROM "
            "items WHERE sku LIKE 'BULK-%'");
  pg_->psql("hub_patterns",
            "INSERT INTO measurements(item_id, name, value_cm) SELECT id, 'hem_circ', 123.5 FROM "
            "items WHERE sku = 'BULK-" +
                std::to_string(n) + "'");
  const std::string q =
      "?station=shop2&base_url=https://files.example/chain&brand=Chain&store_url=https://"
      "shop.example";

  const auto shopify = call(http::verb::get, "/api/export/shopify.csv" + q, "admin-secret");
  ASSERT_EQ(shopify.status, 200) << shopify.body;
  auto rows = csvRows(save("s.csv", shopify.body), ',');
  std::size_t sku = columnOf(rows.at(0), "SKU");
  std::vector<std::string> bulk;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_NE(rows[r], rows[0]) << "a header repeated at row " << r;
    if (rows[r][sku].rfind("BULK-", 0) == 0)
      bulk.push_back(rows[r][sku]);
  }
  ASSERT_EQ(bulk.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(bulk[static_cast<std::size_t>(i)], "BULK-" + std::to_string(i + 1));

  const auto woo = call(http::verb::get, "/api/export/woocommerce.csv" + q, "admin-secret");
  ASSERT_EQ(woo.status, 200) << woo.body;
  rows = csvRows(save("w.csv", woo.body), ',');
  sku = columnOf(rows.at(0), "SKU");
  const std::size_t hem = columnOf(rows[0], "Meta: hem_circ_cm");
  std::size_t wooBulk = 0;
  for (std::size_t r = 1; r < rows.size(); ++r)
    if (rows[r][sku].rfind("BULK-", 0) == 0) {
      ++wooBulk;
      EXPECT_EQ(rows[r][hem], rows[r][sku] == "BULK-" + std::to_string(n) ? "123.5" : "")
          << rows[r][sku];
    }
  EXPECT_EQ(wooBulk, static_cast<std::size_t>(n));

  const auto merchant = call(http::verb::get, "/api/export/merchant.tsv" + q, "admin-secret");
  ASSERT_EQ(merchant.status, 200) << merchant.body;
  rows = csvRows(save("m.tsv", merchant.body), '\t');
  const std::size_t id = columnOf(rows.at(0), "id");
  EXPECT_EQ(std::count_if(rows.begin() + 1, rows.end(),
                          [&](const auto& r) { return r[id].rfind("BULK-", 0) == 0; }),
            n);

  // Refusals are still plain answers, not downloads.
  EXPECT_EQ(call(http::verb::get, "/api/export/shopify.csv" + q, "").status, 401);
  EXPECT_EQ(call(http::verb::get, "/api/export/shopify.csv" + q, "shop1-secret").status, 403);
  EXPECT_EQ(call(http::verb::get, "/api/export/merchant.tsv?station=shop2", "admin-secret").status,
            422);
}

// Python's zipfile on two archives: both pass testzip (every CRC), and they hold the same entry
// names in the same order with the same bytes. Prints what differs, or "same N".
std::string compareZips(const fs::path& a, const fs::path& b) {
  int st = 0;
  return runCommand(
      "/usr/bin/python3 -c 'import sys, zipfile\n"
      "za, zb = zipfile.ZipFile(sys.argv[1]), zipfile.ZipFile(sys.argv[2])\n"
      "assert za.testzip() is None and zb.testzip() is None, \"bad CRC\"\n"
      "na, nb = za.namelist(), zb.namelist()\n"
      "assert na == nb, (\"names differ\", [x for x in na if x not in nb][:5], "
      "[x for x in nb if x not in na][:5])\n"
      "diff = [n for n in na if za.read(n) != zb.read(n)]\n"
      "print(\"differ\", diff[:5]) if diff else print(\"same\", len(na))' " +
          quoted(a) + " " + quoted(b) + " 2>&1",
      st);
}

// catalog.zip is written as it is read (items in pages of 500, shop files in pieces, the central
// directory at the end) and holds what the station's in-memory builder makes of the same items:
// the same entries in the same order, byte for byte (the README's notes too: an item without
// SKU, a pattern that cannot be read), past a page and past the 2,000 items it was capped at.
TEST_F(HubPatternTest, TheChainsCatalogZipIsStreamedAndEqualsTheStationsBuilder) {
  const Json dress = readJson(kDress);
  push("shop1", 301, "G-301", Json{{"base", dress}, {"55", dress}, {"56", dress}});
  push("shop1", 302, "", Json{{"base", dress}});
  push("shop1", 303, "BAD-303", Json{{"base", Json{{"pieces", "not a pattern"}}}});
  pg_->psql("hub_patterns",
            "INSERT INTO items(station_id, local_id, sku, title, price_cents, status, type, "
            "hub_owned, doc) SELECT 'shop1', 200000 + g, 'ZB-' || g, 'Zip skirt ' || g, 1000 + g, "
            "'approved', 'skirt', true, jsonb_build_object('base_size', '38') FROM "
            "generate_series(1, 2100) g");
  pg_->psql("hub_patterns",
            "INSERT INTO measurements(item_id, name, value_cm) SELECT id, 'waist_circ', 70 FROM "
            "items WHERE sku LIKE 'ZB-%'");
  const std::string q =
      "station=shop1&base_url=https://files.example/chain&brand=Chain"
      "&store_url=https://shop.example";
  const auto streamed = call(http::verb::get, "/api/export/catalog.zip?" + q, "admin-secret");
  ASSERT_EQ(streamed.status, 200) << streamed.body.substr(0, 300);
  const auto got = save("streamed.zip", streamed.body);

  // The station's builder (daemon::catalogZip) over the same items, as the hub built it before.
  HubStore store(pg_->url("hub_patterns"), 1);
  daemon::CatalogContent content;
  std::map<std::int64_t, std::string> labels;
  for (const auto& h : store.approvedItems("shop1", true)) {
    daemon::Item it = catalogItemOf(h);
    for (const auto& [size, json] : h.patterns)
      it.sizes.push_back(size);
    content.items.push_back(std::move(it));
    content.sizeGuides.push_back(sizeGuideOf(h));
    content.patterns.push_back(h.patterns);
    labels[h.id] =
        "item " + std::to_string(h.id) + " (" + h.station + " #" + std::to_string(h.localId) + ")";
  }
  ASSERT_GT(content.items.size(), 2100u);
  daemon::RouteMatch m;
  m.query = {{"base_url", "https://files.example/chain"},
             {"brand", "Chain"},
             {"store_url", "https://shop.example"}};
  const auto expected = daemon::catalogZip(
      content, daemon::shopOptions(m, {}), [&store](const std::string& s) { return store.blob(s); },
      [&labels](const daemon::Item& it) { return labels.at(it.id); },
      "GarmCap hub catalog export (station shop1)");
  const auto want = save("built.zip", expected.bytes);
  const std::string cmp = compareZips(got, want);
  EXPECT_EQ(cmp.rfind("same ", 0), 0u) << cmp;
  // Notes made it: the item without SKU and the pattern that cannot be read.
  bool skuNote = false, patternNote = false;
  for (const auto& n : expected.notes) {
    skuNote = skuNote || n.find("#302") != std::string::npos;
    patternNote = patternNote || n.find("#303") != std::string::npos;
  }
  EXPECT_TRUE(skuNote && patternNote);
  int st = 0;
  const std::string unzip = runCommand("unzip -tq " + quoted(got) + " 2>&1", st);
  EXPECT_EQ(st, 0) << unzip;
}

// A raw loopback connection that asks for a download, reads `keep` bytes and then stops reading
// (a small receive buffer, so the hub's writes back up soon).
class StalledClient {
 public:
  StalledClient(std::uint16_t port, const std::string& target, const std::string& token,
                std::size_t keep) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    int small = 4096;
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
      throw std::runtime_error("connect failed");
    const std::string req = "GET " + target +
                            " HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: " + "Bearer " + token +
                            "\r\n\r\n";
    if (::send(fd_, req.data(), req.size(), 0) != static_cast<ssize_t>(req.size()))
      throw std::runtime_error("send failed");
    char buf[4096];
    while (got_.size() < keep) {
      const ssize_t n = ::recv(fd_, buf, std::min(sizeof buf, keep - got_.size()), 0);
      if (n <= 0)
        break;
      got_.append(buf, static_cast<std::size_t>(n));
    }
  }
  ~StalledClient() { ::close(fd_); }
  const std::string& head() const { return got_; }
  /// Reads on until the hub closes the connection: true when it did within `limit`.
  bool closedByHubWithin(std::chrono::seconds limit, std::size_t& total) {
    timeval tv{static_cast<time_t>(limit.count()), 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    total = got_.size();
    char buf[65536];
    for (;;) {
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n == 0 || (n < 0 && errno == ECONNRESET))
        return true;
      if (n < 0)
        return false;
      total += static_cast<std::size_t>(n);
      last_.assign(buf, static_cast<std::size_t>(n));
    }
  }
  const std::string& lastBytes() const { return last_; }

 private:
  int fd_ = -1;
  std::string got_, last_;
};

// A client that stops reading half-way holds its export slot only until a piece of the download
// misses its write deadline (request_timeout_s + the piece's size at min_send_rate): then the
// hub closes the connection without the last chunk, and the slot serves the next export.
TEST_F(HubPatternTest, AStalledDownloadIsCutAndItsExportSlotServesTheNext) {
  // Six items of shop2 with a 2 MB photo each: an archive far larger than the socket buffers.
  pg_->psql("hub_patterns",
            "INSERT INTO images(sha256, bytes, size) SELECT encode(sha256(b), 'hex'), b, "
            "length(b) FROM (SELECT convert_to(repeat(md5(g::text), 65536), 'UTF8') b FROM "
            "generate_series(1, 6) g) x ON CONFLICT DO NOTHING");
  pg_->psql("hub_patterns",
            "INSERT INTO items(station_id, local_id, sku, title, price_cents, status, type, "
            "hub_owned) SELECT 'shop2', 300000 + g, 'BIG-' || g, 'Big photo ' || g, 1000, "
            "'approved', 'skirt', true FROM generate_series(1, 6) g");
  pg_->psql("hub_patterns",
            "INSERT INTO item_images(item_id, kind, sha256, media_type) SELECT i.id, 'product', "
            "encode(sha256(convert_to(repeat(md5((i.local_id - 300000)::text), 65536), 'UTF8')), "
            "'hex'), 'image/jpeg' FROM items i WHERE i.sku LIKE 'BIG-%'");
  HubConfig c;
  c.databaseUrl = pg_->url("hub_patterns");
  c.listenPort = 0;
  c.adminTokenSha256 = tokenHash("admin-secret");
  c.stationTokenSha256 = {{"shop1", tokenHash("shop1-secret")},
                          {"shop2", tokenHash("shop2-secret")}};
  c.requestTimeoutS = 1;     // a piece's deadline: 1 s plus its size at...
  c.minSendRate = 16 << 20;  // ...16 MiB/s: about 1 s for a 2 MB photo
  HubService hub(c);
  hub.start();
  const std::string target = "/api/export/catalog.zip?station=shop2";

  StalledClient a(hub.port(), target, "admin-secret", 1000);
  StalledClient b(hub.port(), target, "admin-secret", 1000);
  ASSERT_EQ(a.head().rfind("HTTP/1.1 200", 0), 0u) << a.head().substr(0, 200);
  ASSERT_EQ(b.head().rfind("HTTP/1.1 200", 0), 0u) << b.head().substr(0, 200);
  // Both slots are held: a third export is told to come back.
  const auto busy =
      e2e::httpCallWith(hub.port(), http::verb::get, target,
                        {{"Host", "127.0.0.1"}, {"Authorization", "Bearer admin-secret"}});
  EXPECT_EQ(busy.status, 503) << busy.body;

  // Neither client reads on: within a few seconds a piece of each misses its deadline, the hub
  // closes both, and the slots serve the next export, written whole.
  const auto stalledAt = std::chrono::steady_clock::now();
  Reply whole;
  while (std::chrono::steady_clock::now() - stalledAt < std::chrono::seconds(30)) {
    whole = e2e::httpCallWith(hub.port(), http::verb::get, target,
                              {{"Host", "127.0.0.1"}, {"Authorization", "Bearer admin-secret"}});
    if (whole.status != 503)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const auto freedAfter =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stalledAt);
  ASSERT_EQ(whole.status, 200) << whole.body.substr(0, 300);
  EXPECT_LT(freedAfter.count(), 15.0);
  std::cout << "slots freed " << freedAfter.count() << " s after the clients stalled\n";
  EXPECT_GT(whole.body.size(), 12u << 20);
  EXPECT_GE(zipNames(save("whole.zip", whole.body)).count("README.txt"), 1u);

  // The stalled clients' connections are closed, their downloads short of the archive and
  // without the last chunk.
  for (auto* client : {&a, &b}) {
    std::size_t total = 0;
    EXPECT_TRUE(client->closedByHubWithin(std::chrono::seconds(10), total));
    EXPECT_LT(total, whole.body.size());
    EXPECT_EQ(client->lastBytes().find("\r\n0\r\n\r\n"), std::string::npos);
  }
  hub.stop();
}

}  // namespace
}  // namespace garmcap::hub
