// HTTP-level tests of the exports (issue 8): the real garmcapd on the simulated rig (bare form,
// then the skirt of rig case_002), every export route read back and compared with what the API
// says about the item. The CSVs are read by a small RFC 4180 reader written here (independent of
// the daemon's writer), the ZIP by Debian's `unzip` (CRCs tested, entries read back).
//
// One capture serves all checks of a test: calibration + capture take most of its run time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "../daemon/csv_reader.h"
#include "daemon_harness.h"

namespace {

using namespace garmcap::e2e;
using Row = std::map<std::string, std::string>;

// The rows of a CSV/TSV export as header name -> value.
std::vector<Row> readCsv(const std::string& text, char sep) {
  const auto records = garmcap::test::readCsvRecords(text, sep);
  std::vector<Row> rows;
  if (records.empty())
    return rows;
  const auto& header = records.front();
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].size() != header.size())
      throw std::runtime_error("CSV record " + std::to_string(r) + " has " +
                               std::to_string(records[r].size()) + " fields, the header " +
                               std::to_string(header.size()));
    Row row;
    for (std::size_t f = 0; f < header.size(); ++f)
      row[header[f]] = records[r][f];
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<std::string> csvHeader(const std::string& text) {
  std::vector<std::string> out(1);
  for (char c : text.substr(0, text.find('\n'))) {
    if (c == ',' || c == '\t')
      out.emplace_back();
    else if (c != '\r' && c != '"')
      out.back() += c;
  }
  return out;
}

// Output of a shell command (bounded by the command itself); exit status in `status`.
std::string run(const std::string& cmd, int& status) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p)
    throw std::runtime_error("cannot run: " + cmd);
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
    out.append(buf, n);
  status = ::pclose(p);
  return out;
}

std::string quoted(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at < text.size()) {
    const auto nl = text.find('\n', at);
    out.push_back(text.substr(at, nl == std::string::npos ? std::string::npos : nl - at));
    if (nl == std::string::npos)
      break;
    at = nl + 1;
  }
  return out;
}

std::vector<std::string> rowsWith(const std::vector<Row>& rows, const std::string& column,
                                  const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& r : rows)
    if (r.count(column) && r.at(column).rfind(prefix, 0) == 0)
      out.push_back(r.at(column));
  return out;
}

// A station with a calibrated form and one captured skirt (SKU `sku`).
struct Captured {
  std::int64_t id = 0;
  Json item;
};

Captured calibrateAndCapture(const Daemon& d, const std::string& sku) {
  auto cal = d.waitJob(d.post("/api/capture/empty").json()["job"]);
  if (cal["state"] != "done")
    throw std::runtime_error("bare-form capture failed: " + cal.dump());
  auto r = d.post("/api/capture", R"({"sku": ")" + sku + "\"}");
  if (r.status != 202)
    throw std::runtime_error("capture refused: " + r.body);
  auto job = d.waitJob(r.json()["job"]);
  if (job["state"] != "done")
    throw std::runtime_error("capture failed: " + job.dump());
  Captured c;
  c.id = job["item_id"];
  c.item = d.get("/api/items/" + std::to_string(c.id)).json();
  return c;
}

std::string itemPath(std::int64_t id) {
  return "/api/items/" + std::to_string(id);
}

const std::string kBase = "https://shop.example/files";
const std::string kQuery =
    "?base_url=" + kBase + "&store_url=https://shop.example&brand=Atelier%20E2E";

// The dressed capture stores the graded run (a pattern per chart size and a size guide), its
// shop files have one variant per graded size, every pattern route serves every size, and the
// catalog ZIP holds all of it. A capture waiting for review is exported only once approved.
TEST(ExportHttp, DressedCaptureExportsItsGradedSizeRun) {
  TempDir dir;
  Daemon d(dir.path(), {}, makeSimulatedRig(dir.path()));
  const std::string sku = "EXP-7";
  const Captured cap = calibrateAndCapture(d, sku);
  const auto& item = cap.item;
  const std::string at = itemPath(cap.id);
  ASSERT_EQ(item["type"], "skirt") << item.dump();

  // --- the graded run in the catalog: "base" (as measured) + every chart size, with a guide.
  const auto sizesJ = item["sizes"];
  ASSERT_TRUE(sizesJ.is_array() && !sizesJ.empty()) << item.dump();
  EXPECT_EQ(sizesJ.front(), "base");
  std::vector<std::string> graded;
  for (const auto& s : sizesJ)
    if (s != "base")
      graded.push_back(s.get<std::string>());
  const std::vector<std::string> chart = {"44", "55", "66", "77", "88"};  // korean_women
  EXPECT_EQ(graded, chart) << "warnings: " << item["warnings"].dump();
  ASSERT_GE(graded.size(), 2u) << item.dump();
  const std::string baseSize = item["base_size"];
  EXPECT_NE(std::find(graded.begin(), graded.end(), baseSize), graded.end()) << baseSize;
  const auto guideReply = d.get(at + "/sizeguide.json");
  ASSERT_EQ(guideReply.status, 200) << guideReply.body;
  const Json guide = guideReply.json();
  EXPECT_EQ(guide["units"], "cm");
  EXPECT_EQ(guide["base_size"], baseSize);
  ASSERT_TRUE(guide["rows"].is_array() && guide["measurements"].is_array()) << guideReply.body;
  std::vector<std::string> guideSizes;
  for (const auto& r : guide["rows"])
    guideSizes.push_back(r["size"]);
  EXPECT_EQ(guideSizes, graded);
  ASSERT_FALSE(guide["measurements"].empty());
  // The piece's own row is what was measured on it, to 0.1 cm; every other row has each value.
  for (const auto& r : guide["rows"])
    for (const auto& name : guide["measurements"]) {
      const std::string n = name;
      if (r["size"] == baseSize) {
        ASSERT_TRUE(item["measurements"].contains(n)) << n;
        EXPECT_NEAR(r["garment"][n].get<double>(), item["measurements"][n].get<double>(), 0.05)
            << n;
      }
      ASSERT_TRUE(r["garment"].contains(n)) << n << " size " << r["size"];
      EXPECT_GT(r["garment"][n].get<double>(), 0) << n << " size " << r["size"];
    }
  // Graded garments grow with the size: the waist of every size is larger than the one before.
  for (std::size_t i = 1; i < graded.size(); ++i)
    EXPECT_GT(guide["rows"][i]["garment"]["waist_circ"].get<double>(),
              guide["rows"][i - 1]["garment"]["waist_circ"].get<double>())
        << graded[i];
  const auto guideCsv = d.get(at + "/sizeguide.csv");
  ASSERT_EQ(guideCsv.status, 200);
  EXPECT_EQ(guideCsv.body.rfind("size,item,", 0), 0u) << guideCsv.body;

  // --- pattern files of every stored size.
  for (const auto& size : sizesJ) {
    const std::string q = "?size=" + size.get<std::string>();
    SCOPED_TRACE("size " + size.get<std::string>());
    const auto pj = d.get(at + "/pattern.json" + q);
    ASSERT_EQ(pj.status, 200) << pj.body;
    ASSERT_FALSE(pj.json()["panels"].empty()) << pj.body.substr(0, 300);
    const auto svg = d.get(at + "/pattern.svg" + q);
    EXPECT_EQ(svg.status, 200) << svg.body;
    EXPECT_EQ(svg.contentType, "image/svg+xml");
    EXPECT_NE(svg.body.find("<svg"), std::string::npos);
    EXPECT_NE(svg.body.find("cm\""), std::string::npos) << "SVG 1:1 carries physical units";
    // The pieces to cut: a cut line per piece, no draft contour hiding the dashed sew line.
    EXPECT_NE(svg.body.find("class=\"cut-line\""), std::string::npos);
    EXPECT_NE(svg.body.find("class=\"sew-line\""), std::string::npos);
    EXPECT_EQ(svg.body.find("id=\"draft-contours\""), std::string::npos);
    const auto dxf = d.get(at + "/pattern.dxf" + q);
    ASSERT_EQ(dxf.status, 200) << dxf.body;
    EXPECT_EQ(dxf.contentType, "application/dxf");
    EXPECT_NE(dxf.body.find("SECTION"), std::string::npos);
    EXPECT_NE(dxf.body.find("EOF"), std::string::npos);
    const std::string label = size == "base" ? baseSize : size.get<std::string>();
    EXPECT_NE(dxf.body.find("Size: " + label), std::string::npos) << "piece text names the size";
    const auto pdf = d.get(at + "/pattern.pdf" + q);
    ASSERT_EQ(pdf.status, 200) << pdf.body;
    EXPECT_EQ(pdf.contentType, "application/pdf");
    EXPECT_EQ(pdf.body.rfind("%PDF-", 0), 0u);
    EXPECT_NE(pdf.body.find("%%EOF"), std::string::npos);
    const auto gc = d.get(at + "/garmentcode.json" + q);
    ASSERT_EQ(gc.status, 200) << gc.body;
    EXPECT_TRUE(gc.json().contains("pattern")) << gc.body.substr(0, 200);
  }
  // Sizes differ: the graded DXFs of the smallest and largest size are not the same file.
  EXPECT_NE(d.get(at + "/pattern.dxf?size=" + graded.front()).body,
            d.get(at + "/pattern.dxf?size=" + graded.back()).body);
  const auto vit = d.get(at + "/measurements.vit");
  ASSERT_EQ(vit.status, 200) << vit.body;
  EXPECT_EQ(vit.contentType, "application/xml");
  EXPECT_NE(vit.body.find("<vit>"), std::string::npos);
  EXPECT_NE(vit.body.find("waist_circ"), std::string::npos);
  const auto gdxf = d.get(at + "/pattern_graded.dxf");
  ASSERT_EQ(gdxf.status, 200) << gdxf.body;
  for (const auto& s : graded)
    EXPECT_NE(gdxf.body.find("Size: " + s), std::string::npos) << s;
  const auto rul = d.get(at + "/pattern_graded.rul");
  ASSERT_EQ(rul.status, 200) << rul.body;
  EXPECT_NE(rul.body.find("SAMPLE SIZE: " + baseSize), std::string::npos)
      << rul.body.substr(0, 400);

  // --- errors: a size the item does not have names the size and the sizes it has.
  for (const char* route : {"pattern.json", "pattern.svg", "pattern.dxf", "pattern.pdf"}) {
    SCOPED_TRACE(route);
    const auto r = d.get(at + "/" + route + "?size=XXL");
    EXPECT_EQ(r.status, 404) << r.body;
    const Json e = r.json();
    ASSERT_TRUE(e.contains("error")) << r.body;
    EXPECT_NE(e["error"].get<std::string>().find("'XXL'"), std::string::npos) << r.body;
    EXPECT_NE(e["error"].get<std::string>().find(graded.front()), std::string::npos) << r.body;
    EXPECT_EQ(d.get(at + "/" + route + "?size=X%20L").status, 400);
    const auto none = d.get("/api/items/987654/" + std::string(route) + "?size=" + graded[0]);
    EXPECT_EQ(none.status, 404) << none.body;
    EXPECT_NE(none.json().value("error", "").find("987654"), std::string::npos) << none.body;
  }
  for (const char* route : {"measurements.vit", "pattern_graded.dxf", "pattern_graded.rul",
                            "sizeguide.json", "garmentcode.json"}) {
    const auto none = d.get("/api/items/987654/" + std::string(route));
    EXPECT_EQ(none.status, 404) << route << ": " << none.body;
    EXPECT_TRUE(none.json().contains("error")) << route;
  }

  // --- review gate: an item waiting for review is in no shop file and its images are not
  // published; approving it puts it in.
  ASSERT_EQ(httpCall(d.port(), http::verb::patch, at, R"({"status": "needs_review"})").status, 200);
  for (const char* f : {"shopify.csv", "woocommerce.csv", "merchant.tsv"}) {
    const auto r = d.get("/api/export/" + std::string(f) + kQuery);
    ASSERT_EQ(r.status, 200) << f << ": " << r.body;
    EXPECT_EQ(r.body.find(sku), std::string::npos) << f << " exports an item waiting for review";
    EXPECT_TRUE(readCsv(r.body, f[0] == 'm' ? '\t' : ',').empty()) << f;
  }
  {
    const auto zip = d.get("/api/export/catalog.zip" + kQuery);
    ASSERT_EQ(zip.status, 200);
    EXPECT_EQ(zip.body.find("patterns/" + std::to_string(cap.id) + "/"), std::string::npos);
    EXPECT_NE(zip.body.find("0 approved items"), std::string::npos);
  }
  EXPECT_EQ(d.get("/api/export/files/images/" + std::to_string(cap.id) + "-product.jpg").status,
            404);
  ASSERT_EQ(httpCall(d.port(), http::verb::patch, at, R"({"status": "approved"})").status, 200);

  // --- Shopify: one product, one variant: the piece in its own size, stock 1. Without a
  // price it is a draft.
  {
    const auto draft = d.get("/api/export/shopify.csv" + kQuery);
    ASSERT_EQ(draft.status, 200) << draft.body;
    const auto rows = readCsv(draft.body, ',');
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows.front().at("Status"), "draft");
  }
  ASSERT_EQ(httpCall(d.port(), http::verb::patch, at, R"({"price_cents": 4990})").status, 200);
  const auto shopify = d.get("/api/export/shopify.csv" + kQuery);
  ASSERT_EQ(shopify.status, 200) << shopify.body;
  EXPECT_EQ(shopify.contentType, "text/csv; charset=utf-8");
  const auto srows = readCsv(shopify.body, ',');
  ASSERT_FALSE(srows.empty());
  std::vector<std::string> variants;
  for (const auto& r : srows) {
    EXPECT_EQ(r.at("URL handle"), "exp-7");
    if (!r.at("Option1 value").empty()) {
      EXPECT_EQ(r.at("Option1 name"), "Size");
      EXPECT_EQ(r.at("SKU"), sku);
      EXPECT_EQ(r.at("Inventory quantity"), "1");
      variants.push_back(r.at("Option1 value"));
    }
  }
  EXPECT_EQ(variants, std::vector<std::string>{baseSize});
  EXPECT_EQ(std::count_if(srows.begin(), srows.end(),
                          [](const Row& r) { return !r.at("Title").empty(); }),
            1);
  const auto& product = srows.front();
  EXPECT_EQ(product.at("Status"), "active");
  {
    // Staff left the title empty: the shop gets the title the API (and so the web UI) shows.
    const auto shown = d.get(at).json();
    ASSERT_EQ(shown.at("title"), "");
    EXPECT_FALSE(shown.at("default_title").get<std::string>().empty());
    EXPECT_EQ(product.at("Title"), shown.at("default_title").get<std::string>());
  }
  EXPECT_EQ(product.at("Vendor"), "Atelier E2E");
  EXPECT_NE(product.at("Description").find("Size guide"), std::string::npos);
  EXPECT_NE(product.at("Description").find("<td>" + baseSize + "</td>"), std::string::npos);
  const auto images = rowsWith(srows, "Product image URL", kBase + "/images/");
  ASSERT_FALSE(images.empty()) << "no image URL under the configured base";
  EXPECT_EQ(images.front(), kBase + "/images/" + std::to_string(cap.id) + "-product.jpg");
  EXPECT_EQ(images.size(), 1u) << "the cut-out is the same photo again: not a second image";
  EXPECT_EQ(d.get("/api/export/files/images/" + std::to_string(cap.id) + "-product.jpg").status,
            200);
  // Made to order: every graded size is a variant, the piece's keeps the item's SKU.
  const auto mto =
      readCsv(d.get("/api/export/shopify.csv" + kQuery + "&made_to_order=1").body, ',');
  std::vector<std::string> mtoSizes;
  for (const auto& r : mto)
    if (!r.at("Option1 value").empty())
      mtoSizes.push_back(r.at("Option1 value"));
  EXPECT_EQ(mtoSizes, graded);
  // Links to this machine are refused unless the shop allows them.
  const auto local = d.get("/api/export/shopify.csv?base_url=http://127.0.0.1:1/files");
  EXPECT_EQ(local.status, 422) << local.body;
  EXPECT_NE(local.json().value("error", "").find("public_base_url"), std::string::npos);
  // With the shop's addresses unset, the address a tablet reached the station by is not taken
  // for the shop's: the CSV names the missing setting, and the ZIP leaves the shop files out with
  // the reason (patterns and photos still in it) instead of publishing LAN links.
  {
    const std::vector<std::pair<std::string, std::string>> lanHost = {
        {"Host", "192.168.1.20:8080"}};
    const auto csv = httpCallWith(d.port(), http::verb::get, "/api/export/shopify.csv", lanHost);
    EXPECT_EQ(csv.status, 422) << csv.body;
    EXPECT_NE(csv.body.find("public_base_url"), std::string::npos) << csv.body;
    EXPECT_EQ(csv.body.find("192.168"), std::string::npos) << csv.body;
    const auto zip = httpCallWith(d.port(), http::verb::get, "/api/export/catalog.zip", lanHost);
    ASSERT_EQ(zip.status, 200) << zip.body;
    EXPECT_EQ(zip.body.find("192.168.1.20"), std::string::npos);
    EXPECT_NE(zip.body.find("shopify.csv left out: "), std::string::npos);
    EXPECT_NE(zip.body.find("No public address is set"), std::string::npos);
    EXPECT_NE(zip.body.find("patterns/" + std::to_string(cap.id) + "/"), std::string::npos);
  }
  // The legacy header set names the same variant.
  const auto legacy = d.get("/api/export/shopify.csv" + kQuery + "&legacy=1");
  ASSERT_EQ(legacy.status, 200);
  EXPECT_EQ(csvHeader(legacy.body).front(), "Handle");
  EXPECT_EQ(rowsWith(readCsv(legacy.body, ','), "Variant SKU", sku).size(), 1u);

  // --- WooCommerce: a simple product with stock 1 and the piece's measurements.
  const auto woo = d.get("/api/export/woocommerce.csv" + kQuery);
  ASSERT_EQ(woo.status, 200) << woo.body;
  const auto wrows = readCsv(woo.body, ',');
  ASSERT_EQ(wrows.size(), 1u);
  EXPECT_EQ(wrows[0].at("Type"), "simple");
  EXPECT_EQ(wrows[0].at("SKU"), sku);
  EXPECT_EQ(wrows[0].at("Stock"), "1");
  EXPECT_EQ(wrows[0].at("Attribute 1 value(s)"), baseSize);
  EXPECT_NEAR(std::stod(wrows[0].at("Meta: waist_circ_cm")),
              item["measurements"]["waist_circ"].get<double>(), 0.051);

  // --- Merchant Center: the piece, with its brand and link.
  const auto merchant = d.get("/api/export/merchant.tsv" + kQuery);
  ASSERT_EQ(merchant.status, 200) << merchant.body;
  const auto mrows = readCsv(merchant.body, '\t');
  ASSERT_EQ(mrows.size(), 1u);
  EXPECT_EQ(mrows[0].at("id"), sku);
  EXPECT_EQ(mrows[0].at("size"), baseSize);
  EXPECT_EQ(mrows[0].at("brand"), "Atelier E2E");
  EXPECT_EQ(mrows[0].at("link"), "https://shop.example/products/exp-7");
  EXPECT_NE(mrows[0].at("product_detail").find("Measurements:"), std::string::npos);

  // --- catalog ZIP: valid (CRCs), and every file the item promises.
  const auto zip = d.get("/api/export/catalog.zip" + kQuery);
  ASSERT_EQ(zip.status, 200);
  EXPECT_EQ(zip.contentType, "application/zip");
  const auto zipPath = dir.path() / "catalog.zip";
  std::ofstream(zipPath, std::ios::binary) << zip.body;
  int st = 0;
  const std::string test = run("unzip -tq " + quoted(zipPath) + " 2>&1", st);
  ASSERT_EQ(st, 0) << "unzip -t: " << test;
  const auto listing = lines(run("unzip -Z1 " + quoted(zipPath), st));
  ASSERT_EQ(st, 0);
  const std::set<std::string> entries(listing.begin(), listing.end());
  const std::string pdir = "patterns/" + std::to_string(cap.id) + "/";
  std::vector<std::string> expected = {"shopify.csv",
                                       "woocommerce.csv",
                                       "merchant.tsv",
                                       "README.txt",
                                       "images/" + std::to_string(cap.id) + "-product.jpg",
                                       pdir + "base.dxf",
                                       pdir + "base.svg",
                                       pdir + "garmentcode.json",
                                       pdir + "graded.dxf",
                                       pdir + "graded.rul",
                                       pdir + "measurements.vit"};
  for (const auto& s : graded) {
    expected.push_back(pdir + s + ".dxf");
    expected.push_back(pdir + s + ".svg");
  }
  for (const auto& e : expected)
    EXPECT_TRUE(entries.count(e)) << "catalog.zip lacks " << e << "; it holds " << listing.size()
                                  << " entries";
  auto entry = [&](const std::string& name) {
    return run("unzip -p " + quoted(zipPath) + " '" + name + "'", st);
  };
  EXPECT_EQ(entry("shopify.csv"), shopify.body) << "the ZIP's CSV is the route's CSV";
  EXPECT_EQ(entry("woocommerce.csv"), woo.body);
  EXPECT_EQ(entry(pdir + graded.back() + ".dxf"),
            d.get(at + "/pattern.dxf?size=" + graded.back()).body);
  const std::string readme = entry("README.txt");
  EXPECT_NE(readme.find("1 approved items"), std::string::npos) << readme;
  EXPECT_EQ(readme.find("Not exported"), std::string::npos) << readme;
  // The shop photo is a JPEG on white at the frame's resolution; the cut-out is not sent again
  // as a second image.
  const std::string jpeg = entry("images/" + std::to_string(cap.id) + "-product.jpg");
  EXPECT_EQ(jpeg.substr(0, 3), "\xff\xd8\xff");
  EXPECT_FALSE(entries.count("images/" + std::to_string(cap.id) + "-cutout.png"));
  EXPECT_EQ(d.terminate(), 0);
}

// Shop files of an empty catalog are a header only; bad export options are a clear 400.
TEST(ExportHttp, EmptyCatalogAndBadOptions) {
  TempDir dir;
  Daemon d(dir.path());
  for (const char* f : {"shopify.csv", "woocommerce.csv", "merchant.tsv"}) {
    const auto r = d.get("/api/export/" + std::string(f));
    ASSERT_EQ(r.status, 200) << f << ": " << r.body;
    EXPECT_TRUE(readCsv(r.body, f[0] == 'm' ? '\t' : ',').empty()) << f;
    EXPECT_GT(csvHeader(r.body).size(), 5u) << f;
  }
  const auto bad = d.get("/api/export/shopify.csv?base_url=ftp://x");
  EXPECT_EQ(bad.status, 400);
  EXPECT_NE(bad.json().value("error", "").find("base_url"), std::string::npos) << bad.body;
  EXPECT_EQ(d.get("/api/export/catalog.zip").status, 200);
  EXPECT_EQ(d.terminate(), 0);
}

// The setup screen's settings: checked as the config's [shop] is, stored (nothing of a refused
// request), used by the exports without any query option, and still there after a restart.
TEST(ExportHttp, ShopSetupSettingsDriveTheExportsAndSurviveARestart) {
  TempDir dir;
  const auto rig = makeSimulatedRig(dir.path());
  auto put = [](const Daemon& d, const std::string& body) {
    return httpCallWith(d.port(), http::verb::put, "/api/settings/shop",
                        {{"Host", "127.0.0.1"}, {"Content-Type", "application/json"}}, body);
  };
  std::int64_t id = 0;
  {
    Daemon d(dir.path(), {}, rig);
    const Json fresh = d.get("/api/settings/shop").json();
    EXPECT_EQ(fresh.at("missing"), Json::array({"brand", "store_url", "public_base_url"}));
    for (const auto& [body, key] : std::vector<std::pair<std::string, std::string>>{
             {R"({"currency": "eur"})", "shop.currency"},
             {R"({"store_url": "ftp://nord.example"})", "shop.store_url"},
             {R"({"brand": "Nord", "colour_of_the_day": "red"})", "colour_of_the_day"},
             {R"({"made_to_order": "yes"})", "shop.made_to_order"},
             {R"({"size_labels": {"55": ""}})", "shop.size_labels.55"},
             {R"(["brand"])", "JSON object"}}) {
      const auto r = put(d, body);
      EXPECT_EQ(r.status, 400) << body << ": " << r.body;
      EXPECT_NE(r.json().value("error", "").find(key), std::string::npos) << r.body;
    }
    EXPECT_EQ(d.get("/api/settings/shop").json().at("saved"), Json::object())
        << "a refused request stored something";
    const auto ok = put(d, R"({"brand": "Atelier Nord", "store_url": "https://nord.example",
                               "public_base_url": "https://cdn.nord.example/files",
                               "currency": "SEK", "size_labels": {"55": "S", "66": "M"}})");
    ASSERT_EQ(ok.status, 200) << ok.body;
    EXPECT_EQ(ok.json().at("missing"), Json::array());
    EXPECT_EQ(ok.json().at("settings").at("currency"), "SEK");
    // A second save changes one key and keeps the others.
    ASSERT_EQ(put(d, R"({"brand": "Atelier Nord AB"})").status, 200);
    const Captured cap = calibrateAndCapture(d, "NORD-1");
    id = cap.id;
    ASSERT_EQ(httpCall(d.port(), http::verb::patch, itemPath(id),
                       R"({"status": "approved", "price_cents": 59900})")
                  .status,
              200);
    EXPECT_EQ(d.terminate(), 0);
  }
  Daemon d(dir.path(), {}, rig);
  const Json after = d.get("/api/settings/shop").json();
  EXPECT_EQ(after.at("settings").at("brand"), "Atelier Nord AB");
  EXPECT_EQ(after.at("settings").at("store_url"), "https://nord.example");
  const auto csv = d.get("/api/export/shopify.csv");
  ASSERT_EQ(csv.status, 200) << csv.body;
  const auto rows = readCsv(csv.body, ',');
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().at("Vendor"), "Atelier Nord AB");
  EXPECT_EQ(rows.front().at("Status"), "active");
  const auto images = rowsWith(rows, "Product image URL", "https://cdn.nord.example/files/images/");
  EXPECT_FALSE(images.empty()) << "no image under the saved public URL";
  EXPECT_EQ(csv.body.find("127.0.0.1"), std::string::npos) << "a loopback link was exported";
  const auto merchant = readCsv(d.get("/api/export/merchant.tsv").body, '\t');
  ASSERT_FALSE(merchant.empty());
  EXPECT_NE(merchant.front().at("price").find("SEK"), std::string::npos)
      << merchant.front().at("price");
  EXPECT_EQ(d.terminate(), 0);
}

}  // namespace
