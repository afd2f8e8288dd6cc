// Graded pattern files at the hub (a real PostgreSQL, HubService on a loopback port): a station
// pushes an item's graded run as the station stores it (a pattern per chart size, graded from
// the pattern as measured by dsw::gradeSizeRun, "base" = as measured, and the size guide built
// from the run), and the hub serves the station's per-item graded files from it:
// pattern_graded.dxf + .rul, nested_grading.svg/.pdf/.dxf, garmentcode.json, measurements.vit.
// Each is read back by an independent reader: ezdxf (Debian's python3-ezdxf) audits the DXFs
// and gives each size's pieces, compared with the pushed pattern of that size; the RUL's size
// list and sample are read by a regular expression; Python's json and XML parsers, pdfinfo.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../common/run_command.h"
#include "../e2e/daemon_harness.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_guide.h"
#include "garmcap/dsw/size_run.h"
#include "garmcap/hub/hub_service.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

using garmcap::testing::runCommand;

using e2e::Json;
using e2e::Reply;
namespace http = e2e::http;
namespace fs = std::filesystem;

class HubGradedTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::postgresBinDir())
      return;
    pg_ = new test::TempPostgres();
    pg_->createDatabase("hub_graded");
    HubConfig c;
    c.databaseUrl = pg_->url("hub_graded");
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
    dir_ = fs::temp_directory_path() / ("garmcap-hubgraded-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static Reply call(const std::string& target, const std::string& token,
                    http::verb verb = http::verb::get, const std::string& body = "") {
    std::vector<std::pair<std::string, std::string>> fields = {{"Host", "127.0.0.1"}};
    if (!token.empty())
      fields.emplace_back("Authorization", "Bearer " + token);
    if (!body.empty())
      fields.emplace_back("Content-Type", "application/json");
    return e2e::httpCallWith(service_->port(), verb, target, fields, body);
  }
  static std::int64_t push(const std::string& station, std::int64_t localId, const Json& item,
                           const Json& patterns) {
    const Json body{
        {"local_id", localId}, {"item", item}, {"deleted", false}, {"patterns", patterns}};
    const auto r = call("/api/hub/push", station + "-secret", http::verb::post, body.dump());
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
test::TempPostgres* HubGradedTest::pg_ = nullptr;
HubService* HubGradedTest::service_ = nullptr;

const fs::path kDesignedDress = fs::path(GARMCAP_TEST_DATA_DIR) / "designs" / "dress_55.json";

// ezdxf's view of a graded DXF-AAMA file: "<size> <height mm>" per block of a piece in a size
// (the block's sew line, layer 14), sorted; "ERRORS n" from its audit first.
std::string gradedBlocks(const fs::path& dxf, const std::vector<std::string>& sizes) {
  std::string list;
  for (const auto& s : sizes)
    list += (list.empty() ? "" : ",") + s;
  int st = 0;
  const std::string out = runCommand(
      "/usr/bin/python3 -c '\n"
      "import sys, ezdxf\n"
      "d = ezdxf.readfile(sys.argv[1]); a = d.audit(); print(\"ERRORS\", len(a.errors))\n"
      "sizes = sys.argv[2].split(\",\")\n"
      "rows = []\n"
      "for b in d.blocks:\n"
      "  if b.name.startswith(\"*\") or b.name.rsplit(\"_\", 1)[-1] not in sizes: continue\n"
      "  for e in b:\n"
      "    if e.dxftype() == \"POLYLINE\" and e.dxf.layer == \"14\":\n"
      "      ys = [v.dxf.location.y for v in e.vertices]\n"
      "      rows.append(\"%s %.1f\" % (b.name.rsplit(\"_\", 1)[-1], max(ys) - min(ys)))\n"
      "print(\"\\n\".join(sorted(rows)))' '" +
          dxf.string() + "' '" + list + "' 2>&1",
      st);
  if (st != 0)
    throw std::runtime_error("ezdxf refused " + dxf.string() + ": " + out);
  return out;
}

TEST_F(HubGradedTest, GradedFilesOfAnyStationsItemAreWrittenFromItsPushedSizeRun) {
  // The station's graded run of a dress measured as 55: every korean_women size, and its guide.
  const drafts::Pattern source = drafts::readPatternJson(kDesignedDress);
  const drafts::SizeChart& chart = drafts::sizeChart("korean_women");
  const auto graded = dsw::gradeSizeRun(source, chart);
  ASSERT_TRUE(graded) << graded.error().message;
  const auto nearest = dsw::sampleSizeOf(source, chart);
  ASSERT_TRUE(nearest);
  const std::string sample = chart.sizes[*nearest];
  const auto guide = dsw::buildSizeGuide(
      *graded, chart, "dress", dsw::shopperMeasurements("dress", drafts::measurePattern(source)),
      *nearest);
  ASSERT_TRUE(guide) << guide.error().message;
  Json patterns{{"base", drafts::patternToJsonValue(source)}};
  for (std::size_t i = 0; i < graded->sizes.size(); ++i)
    patterns[graded->sizes[i]] = drafts::patternToJsonValue(graded->patterns[i]);
  const Json item{{"sku", "GR-1"},
                  {"title", "Graded dress"},
                  {"status", "needs_review"},
                  {"type", "dress"},
                  {"base_size", sample},
                  {"measurements", {{"bust_circ", 88.0}}},
                  {"images", Json::object()},
                  {"size_guide", Json::parse(dsw::sizeGuideJson(*guide))}};
  const std::int64_t id = push("shop1", 1, item, patterns);
  const std::string at = "/api/items/" + std::to_string(id);

  // Graded DXF-AAMA: audited clean; a block per piece and size, each size's pieces as tall as
  // that size's pushed pattern (the hub wrote each size's own pattern, in mm).
  const auto dxf = call(at + "/pattern_graded.dxf", "admin-secret");
  ASSERT_EQ(dxf.status, 200) << dxf.body;
  EXPECT_EQ(dxf.disposition, "attachment; filename=\"GR-1.dxf\"");
  std::vector<std::string> expected;
  for (std::size_t i = 0; i < graded->sizes.size(); ++i)
    for (const auto& panel : graded->patterns[i].panels) {
      double lo = 1e9, hi = -1e9;
      for (const auto& p : panel.outline) {
        lo = std::min(lo, p.y());
        hi = std::max(hi, p.y());
      }
      char row[64];
      std::snprintf(row, sizeof row, "%s %.1f", graded->sizes[i].c_str(), (hi - lo) * 10.0);
      expected.push_back(row);
    }
  std::sort(expected.begin(), expected.end());
  std::string want = "ERRORS 0\n";
  for (const auto& r : expected)
    want += r + "\n";
  EXPECT_EQ(gradedBlocks(save("g.dxf", dxf.body), graded->sizes), want);

  // The grade rule table: the guide's sizes in order, the item's size as the sample.
  const auto rul = call(at + "/pattern_graded.rul", "shop1-secret");
  ASSERT_EQ(rul.status, 200) << rul.body;
  int st = 0;
  const std::string rulOut = runCommand(
      "/usr/bin/python3 -c 'import re, sys; t = open(sys.argv[1], encoding=\"ascii\").read(); "
      "print(\" \".join(re.search(r\"^SIZE LIST:(.*)$\", t, re.M).group(1).split()), \"/\", "
      "re.search(r\"^SAMPLE SIZE:\\s*(\\S+)\", t, re.M).group(1))' '" +
          save("g.rul", rul.body).string() + "' 2>&1",
      st);
  ASSERT_EQ(st, 0) << rulOut;
  std::string sizes;
  for (const auto& s : graded->sizes)
    sizes += (sizes.empty() ? "" : " ") + s;
  EXPECT_EQ(rulOut, sizes + " / " + sample + "\n");

  // Nested grading: the DXF audited clean with a layer per size; the SVG parsed, a polygon per
  // piece and size; the PDF one page.
  const auto ndxf = call(at + "/nested_grading.dxf", "admin-secret");
  ASSERT_EQ(ndxf.status, 200) << ndxf.body;
  const std::string layers = runCommand(
      "/usr/bin/python3 -c 'import sys, ezdxf; d = ezdxf.readfile(sys.argv[1]); "
      "print(len(d.audit().errors), \" \".join(sorted(l.dxf.name for l in d.layers if "
      "l.dxf.name.startswith(\"SIZE_\"))))' '" +
          save("n.dxf", ndxf.body).string() + "' 2>&1",
      st);
  ASSERT_EQ(st, 0) << layers;
  std::string sizeLayers;
  for (const auto& s : graded->sizes)
    sizeLayers += " SIZE_" + s;
  EXPECT_EQ(layers, "0" + sizeLayers + "\n");
  const auto nsvg = call(at + "/nested_grading.svg", "admin-secret");
  ASSERT_EQ(nsvg.status, 200) << nsvg.body;
  const std::string polygons = runCommand(
      "/usr/bin/python3 -c 'import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1])"
      ".getroot(); ps = [e for e in r.iter() if e.tag.endswith(\"polygon\") and "
      "e.get(\"data-size\")]; print(len(ps), sum(1 for e in ps if e.get(\"data-sample\")))' '" +
          save("n.svg", nsvg.body).string() + "' 2>&1",
      st);
  ASSERT_EQ(st, 0) << polygons;
  const std::size_t pieces = source.panels.size();
  EXPECT_EQ(polygons,
            std::to_string(pieces * graded->sizes.size()) + " " + std::to_string(pieces) + "\n");
  const auto npdf = call(at + "/nested_grading.pdf", "admin-secret");
  ASSERT_EQ(npdf.status, 200) << npdf.body;
  const std::string info =
      runCommand("pdfinfo '" + save("n.pdf", npdf.body).string() + "' 2>&1", st);
  ASSERT_EQ(st, 0) << info;
  EXPECT_NE(info.find("\nPages:           1\n"), std::string::npos) << info;

  // GarmentCode JSON of the pattern as measured and the body as Valentina reads it: parsed by
  // Python.
  const auto gc = call(at + "/garmentcode.json", "admin-secret");
  ASSERT_EQ(gc.status, 200) << gc.body;
  EXPECT_EQ(gc.disposition, "attachment; filename=\"GR-1_base_specification.json\"");
  const std::string gcOut = runCommand(
      "/usr/bin/python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); "
      "print(type(d).__name__, len(d) > 0)' '" +
          save("g.json", gc.body).string() + "' 2>&1",
      st);
  ASSERT_EQ(st, 0) << gcOut;
  EXPECT_EQ(gcOut, "dict True\n");
  EXPECT_EQ(call(at + "/garmentcode.json?size=XXL", "admin-secret").status, 404);
  // Every graded size too (a graded size was refused 422: "seam 'skirt_side' ... does not end
  // on a corner"; tests/dsw/graded_garmentcode_test.cpp reads the JSON back against the panels).
  for (const auto& size : graded->sizes) {
    const auto g = call(at + "/garmentcode.json?size=" + size, "admin-secret");
    EXPECT_EQ(g.status, 200) << size << ": " << g.body.substr(0, 300);
    EXPECT_EQ(g.disposition, "attachment; filename=\"GR-1_" + size + "_specification.json\"");
  }
  const auto vit = call(at + "/measurements.vit", "admin-secret");
  ASSERT_EQ(vit.status, 200) << vit.body;
  const std::string vitOut = runCommand(
      "/usr/bin/python3 -c 'import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1])"
      ".getroot(); print(r.tag, len(r.findall(\".//m\")) > 0)' '" +
          save("b.vit", vit.body).string() + "' 2>&1",
      st);
  ASSERT_EQ(st, 0) << vitOut;
  EXPECT_EQ(vitOut, "vit True\n");

  // Who may read them: the item's station and the admin; another station gets a 404, nobody a
  // 401. An item with one pattern has no graded run (404), as at the station.
  EXPECT_EQ(call(at + "/pattern_graded.dxf", "shop2-secret").status, 404);
  EXPECT_EQ(call(at + "/pattern_graded.rul", "").status, 401);
  const std::int64_t single =
      push("shop2", 1, Json{{"sku", "GR-2"}, {"status", "needs_review"}, {"type", "dress"}},
           Json{{"base", drafts::patternToJsonValue(source)}});
  const auto none =
      call("/api/items/" + std::to_string(single) + "/pattern_graded.dxf", "shop2-secret");
  EXPECT_EQ(none.status, 404);
  EXPECT_NE(none.body.find("fewer than two graded sizes"), std::string::npos) << none.body;
}

}  // namespace
}  // namespace garmcap::hub
