// HTTP-level tests of the exports (issue 8): the real garmcapd on the simulated rig (bare form,
// then the skirt of rig case_002), every export route read back and compared with what the API
// says about the item. The CSVs are read by a small RFC 4180 reader written here (independent of
// the daemon's writer), the ZIP by Debian's `unzip` (CRCs tested, entries read back).
//
// One capture serves all checks of a test: calibration + capture take most of its run time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <string>
#include <tuple>
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
  // case_002's skirt is navy with light-blue dots: a print, in every attribute that says so.
  EXPECT_EQ(item["attributes"].value("pattern", ""), "print") << item["attributes"].dump();
  EXPECT_EQ(item["attributes"].value("fabric", ""), "print") << item["attributes"].dump();
  EXPECT_EQ(item["attributes"].value("color", "").substr(0, 4), "Navy") << item["attributes"];

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
  // The chart's multisize table (Valentina reads it: export_test VstExport.*), every size
  // labelled; an unknown chart a 404 naming the known ones.
  const auto vst = d.get("/api/size_charts/korean_women.vst");
  ASSERT_EQ(vst.status, 200) << vst.body;
  EXPECT_EQ(vst.contentType, "application/xml");
  EXPECT_NE(vst.body.find("<vst>"), std::string::npos);
  EXPECT_NE(vst.body.find("<dimension type=\"y\" base=\"66\" min=\"44\" max=\"88\""),
            std::string::npos)
      << vst.body.substr(0, 400);
  for (const char* s : {"44", "55", "66", "77", "88"})
    EXPECT_NE(vst.body.find(std::string("label=\"") + s + "\""), std::string::npos) << s;
  const auto noChart = d.get("/api/size_charts/martian.vst");
  EXPECT_EQ(noChart.status, 404) << noChart.body;
  EXPECT_NE(noChart.body.find("korean_women"), std::string::npos) << noChart.body;
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
  EXPECT_EQ(mrows[0].at("pattern"), "print");
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
  // The same photo as WebP beside it, read by libwebp's own `dwebp` (not OpenCV, which wrote
  // it): the JPEG's size, and the same picture (mean difference a few levels of 255).
  const std::string webpName = "images/" + std::to_string(cap.id) + "-product_webp.webp";
  ASSERT_TRUE(entries.count(webpName)) << "catalog.zip lacks " << webpName;
  const std::string webp = entry(webpName);
  EXPECT_EQ(webp.substr(0, 4), "RIFF");
  EXPECT_EQ(webp.substr(8, 4), "WEBP");
  EXPECT_EQ(
      webp,
      d.get("/api/export/files/images/" + std::to_string(cap.id) + "-product_webp.webp").body);
  std::ofstream(dir.path() / "product.webp", std::ios::binary) << webp;
  std::ofstream(dir.path() / "product.jpg", std::ios::binary) << jpeg;
  const std::string dw = run("dwebp -ppm " + quoted(dir.path() / "product.webp") + " -o " +
                                 quoted(dir.path() / "product.ppm") + " 2>&1",
                             st);
  ASSERT_EQ(st, 0) << "dwebp: " << dw;
  const cv::Mat fromWebp = cv::imread((dir.path() / "product.ppm").string(), cv::IMREAD_COLOR);
  const cv::Mat fromJpeg = cv::imread((dir.path() / "product.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(fromWebp.empty());
  ASSERT_FALSE(fromJpeg.empty());
  ASSERT_EQ(fromWebp.size(), fromJpeg.size());
  cv::Mat diff;
  cv::absdiff(fromWebp, fromJpeg, diff);
  const cv::Scalar meanDiff = cv::mean(diff);
  EXPECT_LT((meanDiff[0] + meanDiff[1] + meanDiff[2]) / 3, 3.0) << "WebP and JPEG differ";
  // The shop files keep linking the JPEG only (every shop imports it).
  EXPECT_EQ(shopify.body.find(".webp"), std::string::npos);
  EXPECT_EQ(woo.body.find(".webp"), std::string::npos);
  EXPECT_EQ(d.terminate(), 0);
}

// The number after "Pages:" in pdfinfo's report (poppler: a reader independent of the writer),
// and the page size line; -1 when pdfinfo refused the file.
struct PdfInfo {
  int pages = -1;
  std::string pageSize;
};
PdfInfo pdfInfo(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
  int st = 0;
  const std::string out = run("pdfinfo " + quoted(file) + " 2>&1", st);
  PdfInfo info;
  if (st != 0)
    return info;
  for (const auto& l : lines(out)) {
    if (l.rfind("Pages:", 0) == 0)
      info.pages = std::stoi(l.substr(6));
    if (l.rfind("Page size:", 0) == 0)
      info.pageSize = l.substr(10);
  }
  return info;
}

// ezdxf (Debian's python3-ezdxf, as the drafts DXF tests) reads the file and audits it clean.
std::string ezdxfAudit(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
  int st = 0;
  const std::string out =
      run("/usr/bin/python3 -c 'import sys, ezdxf; a = ezdxf.readfile(sys.argv[1]).audit(); "
          "print([str(e) for e in a.errors]); sys.exit(1 if a.has_errors else 0)' " +
              quoted(file) + " 2>&1",
          st);
  return st == 0 ? "" : out;
}

// `garmcap marker` on pattern JSON files (label per file): its JSON report.
Json cliMarker(const std::vector<std::pair<std::string, std::filesystem::path>>& patterns,
               const std::string& width) {
  std::string cmd = std::string(GARMCAP_BIN_DIR) + "/garmcap marker --width " + width;
  for (const auto& [label, file] : patterns)
    cmd += " --pattern " + quoted(file) + " --label " + label;
  int st = 0;
  const std::string out = run(cmd + " 2>&1", st);
  if (st != 0)
    throw std::runtime_error(cmd + ": " + out);
  return Json::parse(out);
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

// Issue 18's files over HTTP: the pattern PDF tiled for A4, US Letter or A0, the nested
// grading of the size run, and markers; each read back by an independent reader (pdfinfo,
// ezdxf), the marker compared with the CLI's on the same patterns, bad queries a 400 naming the
// query, a marker that cannot be laid a 422 saying why.
TEST(ExportHttp, TiledPdfNestedGradingAndMarkers) {
  TempDir dir;
  Daemon d(dir.path(), {}, makeSimulatedRig(dir.path()));
  const Captured cap = calibrateAndCapture(d, "PRN-1");
  const std::string at = itemPath(cap.id);
  const std::string baseSize = cap.item["base_size"];
  std::vector<std::string> graded;
  for (const auto& s : cap.item["sizes"])
    if (s != "base")
      graded.push_back(s);
  ASSERT_GE(graded.size(), 2u) << cap.item.dump();

  // --- pattern.pdf by paper: A4 as before the query, tiles of the paper's size, an A0 sheet
  // takes fewer pages than A4 tiles.
  std::map<std::string, PdfInfo> pdfs;
  for (const auto& [paper, file, size] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"", "_A4.pdf", "(A4)"},
           {"a4", "_A4.pdf", "(A4)"},
           {"letter", "_Letter.pdf", "(letter)"},
           {"A0", "_A0.pdf", "2383.94 x 3370.39 pts"}}) {
    SCOPED_TRACE("paper " + paper);
    const auto r = d.get(at + "/pattern.pdf" + (paper.empty() ? "" : "?paper=" + paper));
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.contentType, "application/pdf");
    EXPECT_EQ(r.disposition, "attachment; filename=\"PRN-1_base" + file + "\"");
    const PdfInfo info = pdfInfo(dir.path() / "p.pdf", r.body);
    ASSERT_GT(info.pages, 0) << "pdfinfo refused the PDF";
    EXPECT_NE(info.pageSize.find(size), std::string::npos) << info.pageSize;
    pdfs[paper] = info;
  }
  EXPECT_EQ(pdfs[""].pages, pdfs["a4"].pages);
  EXPECT_GT(pdfs["a4"].pages, pdfs["A0"].pages);
  EXPECT_GE(pdfs["A0"].pages, 1);
  for (const char* bad : {"b5", "a44", "%20"}) {
    const auto r = d.get(at + "/pattern.pdf?paper=" + bad);
    EXPECT_EQ(r.status, 400) << bad << ": " << r.body;
    EXPECT_NE(r.json().value("error", "").find("'paper' must be a4, letter or a0"),
              std::string::npos)
        << r.body;
  }

  // --- nested grading: every graded size in one drawing, the sample (the piece's size) marked.
  const auto nsvg = d.get(at + "/nested_grading.svg");
  ASSERT_EQ(nsvg.status, 200) << nsvg.body;
  EXPECT_EQ(nsvg.contentType, "image/svg+xml");
  EXPECT_EQ(nsvg.disposition, "attachment; filename=\"PRN-1_nested_grading.svg\"");
  const std::size_t pieces = count(nsvg.body, "class=\"piece\"");
  EXPECT_GT(pieces, 0u);
  for (const auto& s : graded)
    EXPECT_EQ(count(nsvg.body, "<polygon data-size=\"" + s + "\""), pieces) << s;
  EXPECT_EQ(count(nsvg.body, "<polygon data-size=\"" + baseSize + "\" data-sample=\"1\""), pieces)
      << "the sample is the piece's own size " << baseSize;
  const auto npdf = d.get(at + "/nested_grading.pdf");
  ASSERT_EQ(npdf.status, 200) << npdf.body;
  EXPECT_EQ(npdf.contentType, "application/pdf");
  EXPECT_EQ(npdf.disposition, "attachment; filename=\"PRN-1_nested_grading.pdf\"");
  EXPECT_EQ(pdfInfo(dir.path() / "n.pdf", npdf.body).pages, 1);
  const auto ndxf = d.get(at + "/nested_grading.dxf");
  ASSERT_EQ(ndxf.status, 200) << ndxf.body;
  EXPECT_EQ(ndxf.contentType, "application/dxf");
  EXPECT_EQ(ndxf.disposition, "attachment; filename=\"PRN-1_nested_grading.dxf\"");
  EXPECT_EQ(ezdxfAudit(dir.path() / "n.dxf", ndxf.body), "");
  for (const auto& s : graded)
    EXPECT_NE(ndxf.body.find("SIZE_" + s), std::string::npos) << s;

  // --- markers. Default: the piece as measured on 150 cm, as `garmcap marker` lays the same
  // pattern (libnest2d is deterministic: the same length and efficiency).
  const auto base = dir.path() / "base.json";
  std::ofstream(base) << d.get(at + "/pattern.json").body;
  const auto mj = d.get(at + "/marker.json");
  ASSERT_EQ(mj.status, 200) << mj.body;
  EXPECT_EQ(mj.contentType, "application/json");
  const Json m = mj.json();
  EXPECT_EQ(m["sizes"], Json::array({baseSize}));
  EXPECT_EQ(m["fabric_width_cm"], 150.0);
  ASSERT_TRUE(m["pieces"].is_array());
  EXPECT_EQ(m["piece_count"], m["pieces"].size());
  const double eff = m["efficiency"];
  EXPECT_GT(eff, 0.3);
  EXPECT_LE(eff, 1.0);
  EXPECT_NEAR(eff, m["piece_area_cm2"].get<double>() / (m["length_cm"].get<double>() * 150.0),
              1e-12);
  const Json cli = cliMarker({{baseSize, base}}, "150");
  EXPECT_DOUBLE_EQ(eff, cli["efficiency"].get<double>());
  EXPECT_DOUBLE_EQ(m["length_cm"].get<double>(), cli["length_cm"].get<double>());
  EXPECT_EQ(m["piece_count"], cli["pieces"].size());

  // Two graded sizes on 137.5 cm, against the CLI on the same two patterns.
  const std::string two = graded.front() + "," + graded.back();
  std::vector<std::pair<std::string, std::filesystem::path>> files;
  for (const auto& s : {graded.front(), graded.back()}) {
    files.emplace_back(s, dir.path() / (s + ".json"));
    std::ofstream(files.back().second) << d.get(at + "/pattern.json?size=" + s).body;
  }
  const auto run2 = d.get(at + "/marker.json?width=137.5&sizes=" + two);
  ASSERT_EQ(run2.status, 200) << run2.body;
  const Json m2 = run2.json();
  EXPECT_EQ(m2["sizes"], Json::array({graded.front(), graded.back()}));
  EXPECT_EQ(m2["fabric_width_cm"], 137.5);
  const Json cli2 = cliMarker(files, "137.5");
  EXPECT_DOUBLE_EQ(m2["efficiency"].get<double>(), cli2["efficiency"].get<double>());
  EXPECT_DOUBLE_EQ(m2["length_cm"].get<double>(), cli2["length_cm"].get<double>());
  EXPECT_EQ(m2["piece_count"].get<std::size_t>(), 2 * m["piece_count"].get<std::size_t>());
  {
    // garmcapctl fetches the same marker through the same route, and refuses an option that does
    // not go with the file it asks for.
    const std::string ctl = std::string(GARMCAP_BIN_DIR) +
                            "/garmcapctl --url http://127.0.0.1:" + std::to_string(d.port()) +
                            " export " + std::to_string(cap.id);
    int status = 0;
    const std::string out =
        run(ctl + " --what marker.json --width 137.5 --sizes " + two + " 2>&1", status);
    ASSERT_EQ(status, 0) << out;
    const Json viaCtl = Json::parse(out);
    EXPECT_DOUBLE_EQ(viaCtl["efficiency"].get<double>(), m2["efficiency"].get<double>());
    EXPECT_DOUBLE_EQ(viaCtl["length_cm"].get<double>(), m2["length_cm"].get<double>());
    const std::string badPaper = run(ctl + " --what pattern.svg --paper a4 2>&1", status);
    EXPECT_NE(status, 0);
    EXPECT_NE(badPaper.find("--paper goes with --what pattern.pdf"), std::string::npos) << badPaper;
    const std::string badWidth = run(ctl + " --what marker.json --width 20 2>&1", status);
    EXPECT_NE(status, 0);
    EXPECT_NE(badWidth.find("width"), std::string::npos) << badWidth;
  }
  std::printf(
      "pattern.pdf pages: A4 %d, Letter %d, A0 %d; marker %s on 150 cm: %.1f cm, %.1f %%; "
      "%s on 137.5 cm: %.1f cm, %.1f %%\n",
      pdfs["a4"].pages, pdfs["letter"].pages, pdfs["A0"].pages, baseSize.c_str(),
      m["length_cm"].get<double>(), 100 * eff, two.c_str(), m2["length_cm"].get<double>(),
      100 * m2["efficiency"].get<double>());

  const std::string q = "?width=137.5&sizes=" + two;
  const std::string name = "PRN-1_marker_" + graded.front() + "-" + graded.back() + "_137.5cm";
  const auto msvg = d.get(at + "/marker.svg" + q);
  ASSERT_EQ(msvg.status, 200) << msvg.body;
  EXPECT_EQ(msvg.contentType, "image/svg+xml");
  EXPECT_EQ(msvg.disposition, "attachment; filename=\"" + name + ".svg\"");
  EXPECT_EQ(count(msvg.body, "class=\"piece\""), m2["piece_count"].get<std::size_t>());
  const auto mpdf = d.get(at + "/marker.pdf" + q);
  ASSERT_EQ(mpdf.status, 200) << mpdf.body;
  EXPECT_EQ(mpdf.contentType, "application/pdf");
  EXPECT_EQ(mpdf.disposition, "attachment; filename=\"" + name + ".pdf\"");
  EXPECT_EQ(pdfInfo(dir.path() / "m.pdf", mpdf.body).pages, 1);
  const auto mdxf = d.get(at + "/marker.dxf" + q);
  ASSERT_EQ(mdxf.status, 200) << mdxf.body;
  EXPECT_EQ(mdxf.contentType, "application/dxf");
  EXPECT_EQ(mdxf.disposition, "attachment; filename=\"" + name + ".dxf\"");
  EXPECT_EQ(ezdxfAudit(dir.path() / "m.dxf", mdxf.body), "");

  // Bad queries: a 400 naming the query and what is wrong with it.
  for (const auto& [query, says] : std::vector<std::pair<std::string, std::string>>{
           {"width=abc", "'width'"},
           {"width=20", "from 50 to 400"},
           {"width=401", "from 50 to 400"},
           {"width=nan", "'width'"},
           {"width=150cm", "'150cm'"},
           {"sizes=XXL", "no pattern for size 'XXL' (sizes: base, " + graded.front()},
           {"sizes=" + graded.front() + ",", "comma list"},
           {"sizes=" + graded.front() + "," + graded.front(), "twice"},
           {"sizes=a%20b", "comma list"}}) {
    SCOPED_TRACE(query);
    const auto r = d.get(at + "/marker.json?" + query);
    EXPECT_EQ(r.status, 400) << r.body;
    EXPECT_NE(r.json().value("error", "").find(says), std::string::npos) << r.body;
  }
  // How many sizes one marker takes is no longer a fixed count of the query: the pieces are
  // bounded by the station's [marker] max_pieces (station_test.cpp,
  // MarkerPieceLimitIsTheConfigsAndIsNamedWhenExceeded). A piece wider than the fabric: the marker
  // cannot be laid.
  const auto narrow = d.get(at + "/marker.svg?width=50");
  EXPECT_EQ(narrow.status, 422) << narrow.body;
  const std::string why = narrow.json().value("error", "");
  EXPECT_NE(why.find("wider than the fabric (50.0 cm)"), std::string::npos) << narrow.body;
  EXPECT_EQ(why.rfind("marker: panel '", 0), 0u) << "names the piece: " << narrow.body;
  for (const char* route : {"marker.json", "nested_grading.svg", "pattern.pdf?paper=a0"}) {
    const auto none = d.get("/api/items/987654/" + std::string(route));
    EXPECT_EQ(none.status, 404) << route << ": " << none.body;
    EXPECT_NE(none.json().value("error", "").find("987654"), std::string::npos) << none.body;
  }
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
