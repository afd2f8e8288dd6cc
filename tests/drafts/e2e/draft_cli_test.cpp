// End-to-end: `garmcap draft` and `garmcap measure` as a user runs them (the built binary).
// Good input gives pattern JSON the reader accepts and an SVG a real XML parser accepts; bad
// input gives one "garmcap: error: <reason>" line naming the file, field or value, and exit 1.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "common/garmcap_cli.h"

namespace {

using garmcap::testing::CliResult;
using garmcap::testing::runGarmcap;
using garmcap::testing::TempDir;
using garmcap::testing::writeText;

const std::string kData = GARMCAP_TEST_DATA_DIR;

// The refusal contract: nothing on stdout, one error line naming every `needles`, status 1.
void expectRefused(const CliResult& r, std::initializer_list<std::string> needles) {
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.rfind("garmcap: error: ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  for (const auto& n : needles)
    EXPECT_NE(r.err.find(n), std::string::npos) << "no '" << n << "' in: " << r.err;
}

bool haveXmllint() {
  return std::system("command -v xmllint >/dev/null 2>&1") == 0;
}

TEST(DraftCli, ListAndChartsPrintJson) {
  const CliResult list = runGarmcap("draft --list");
  ASSERT_EQ(list.status, 0) << list.err;
  const auto types = nlohmann::json::parse(list.out).at("types");
  ASSERT_GE(types.size(), 8u);
  for (const auto& t : types) {
    EXPECT_TRUE(t.at("name").is_string());
    EXPECT_FALSE(t.at("measurements").empty()) << t.at("name");
  }
  const CliResult charts = runGarmcap("draft --charts");
  ASSERT_EQ(charts.status, 0) << charts.err;
  std::map<std::string, nlohmann::json> byName;
  const auto chartsJson = nlohmann::json::parse(charts.out);
  for (const auto& c : chartsJson.at("charts"))
    byName[c.at("name").get<std::string>()] = c;
  ASSERT_TRUE(byName.count("korean_women"));
  ASSERT_TRUE(byName.count("french_women"));
  EXPECT_EQ(byName["korean_women"]["sizes"], nlohmann::json({"44", "55", "66", "77", "88"}));
  EXPECT_NE(byName["french_women"]["source"].get<std::string>().find("Gilewska"),
            std::string::npos);
}

// Every type at size 55: the pattern JSON reads back through `measure`, the SVG is XML.
TEST(DraftCli, EveryTypeDraftsMeasuresAndWritesSvg) {
  const TempDir d("draft_cli_types");
  const auto types = nlohmann::json::parse(runGarmcap("draft --list").out).at("types");
  for (const auto& t : types) {
    const std::string type = t.at("name");
    SCOPED_TRACE(type);
    const std::string json = d / (type + ".json"), svg = d / (type + ".svg");
    const CliResult r = runGarmcap(
        "draft --type " + type + " --size 55 --chart korean_women --out " + json + " --svg " + svg);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const auto pattern = nlohmann::json::parse(garmcap::testing::readText(json));
    EXPECT_EQ(pattern.at("type"), type);
    const CliResult m = runGarmcap("measure --pattern " + json);
    ASSERT_EQ(m.status, 0) << m.err;
    const auto measured = nlohmann::json::parse(m.out);
    EXPECT_EQ(measured.at("type"), type);
    EXPECT_EQ(measured.at("units"), "cm");
    EXPECT_FALSE(measured.at("measurements").empty());
    const std::string text = garmcap::testing::readText(svg);
    EXPECT_NE(text.find("<svg"), std::string::npos);
    EXPECT_NE(text.find("cm\" viewBox="), std::string::npos);  // true scale
    if (haveXmllint()) {
      EXPECT_EQ(std::system(("xmllint --noout '" + svg + "'").c_str()), 0) << svg;
    }
  }
}

// A skirt for the seed's size 55 measures the body plus the recipe's ease; a measurements
// file (JSON or Valentina .vit) drafts the same pattern as the chart size it holds.
TEST(DraftCli, MeasurementFilesDraftLikeTheChartSize) {
  const TempDir d("draft_cli_files");
  const std::string body = kData + "/bodies/table4_2_55.json";
  ASSERT_EQ(
      runGarmcap("draft --type skirt_h --measurements " + body + " --out " + (d / "file.json"))
          .status,
      0);
  ASSERT_EQ(
      runGarmcap("draft --type skirt_h --size 55 --chart korean_women --out " + (d / "chart.json"))
          .status,
      0);
  EXPECT_EQ(nlohmann::json::parse(garmcap::testing::readText(d / "file.json")),
            nlohmann::json::parse(garmcap::testing::readText(d / "chart.json")));
  const auto m = nlohmann::json::parse(runGarmcap("measure --pattern " + (d / "file.json")).out)
                     .at("measurements");
  EXPECT_GT(m.at("hip_circ").get<double>(), 90.0);
  EXPECT_LT(m.at("hip_circ").get<double>(), 90.0 + 10.0);
  EXPECT_GT(m.at("waist_circ").get<double>(), 65.0 - 0.001);
  writeText(d / "b.vit", R"(<?xml version="1.0" encoding="UTF-8"?>
<vit><version>0.3.3</version><read-only>false</read-only><notes/><unit>cm</unit><pm_system>998</pm_system>
<personal><customer/><birth-date>1800-01-01</birth-date><gender>female</gender><email/></personal>
<body-measurements>
<m name="waist_circ" value="65"/><m name="hip_circ" value="90"/><m name="waist_to_hip_b" value="19"/>
<m name="height" value="171"/>
</body-measurements></vit>
)");
  const CliResult vit = runGarmcap("draft --type skirt_h --measurements " + (d / "b.vit") +
                                   " --out " + (d / "v.json"));
  EXPECT_EQ(vit.status, 0) << vit.err;
}

TEST(DraftCli, BadOptionsAreRefused) {
  const TempDir d("draft_cli_options");
  const std::string out = " --out " + (d / "p.json");
  expectRefused(runGarmcap("draft --size 55 --chart korean_women" + out), {"--type"});
  expectRefused(runGarmcap("draft --type skirt_h --size 55 --chart korean_women"), {"--out"});
  expectRefused(runGarmcap("draft --type cape --size 55 --chart korean_women" + out),
                {"cape", "skirt_h"});
  expectRefused(runGarmcap("draft --type skirt_h --size 55 --chart martian" + out),
                {"martian", "korean_women"});
  expectRefused(runGarmcap("draft --type skirt_h --size 99 --chart korean_women" + out),
                {"korean_women", "'99'"});
  expectRefused(runGarmcap("draft --type skirt_h --size 55" + out), {"--chart"});
  expectRefused(runGarmcap("draft --type skirt_h --size 55 --chart korean_women --measurements " +
                           kData + "/bodies/table4_2_55.json" + out),
                {"either"});
  expectRefused(runGarmcap("draft --type skirt_h --size 55 --chart korean_women --set ease" + out),
                {"--set 'ease'", "name=value"});
  expectRefused(
      runGarmcap("draft --type skirt_h --size 55 --chart korean_women --set hip_ease=wide" + out),
      {"'wide'", "not a number"});
  expectRefused(
      runGarmcap("draft --type skirt_h --size 55 --chart korean_women --colour red" + out),
      {"--colour"});
  // Nothing was written by any refused command.
  EXPECT_FALSE(std::filesystem::exists(d / "p.json"));
  // An output that cannot be written (its folder is a file) names the file.
  writeText(d / "file", "");
  expectRefused(runGarmcap("draft --type skirt_h --size 55 --chart korean_women --out " +
                           (d / "file/p.json")),
                {d / "file/p.json"});
}

// Issue 18: `garmcap marker --max-pieces` sets the piece limit; more pieces are refused before
// nesting, naming the count and the limit; a limit that is no number of pieces is refused.
TEST(MarkerCli, MaxPiecesIsAnOptionAndItsRefusalNamesTheLimit) {
  const std::string skirt = "marker --type skirt_h --chart korean_women --size 66";
  expectRefused(runGarmcap(skirt + " --size 77 --max-pieces 2"),
                {"pieces to lay", "limit of 2 pieces", "max_pieces"});
  expectRefused(runGarmcap(skirt + " --max-pieces 0"), {"--max-pieces"});
  const CliResult ok = runGarmcap(skirt + " --max-pieces 3");
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(ok.out)["piece_count"], 3);
}

TEST(DraftCli, BadMeasurementFilesNameTheFileAndThePlace) {
  const TempDir d("draft_cli_bodies");
  const std::string out = " --out " + (d / "p.json");
  auto draftSkirt = [&](const std::string& file) {
    return runGarmcap("draft --type skirt_h --measurements " + file + out);
  };
  expectRefused(draftSkirt(d / "absent.json"), {d / "absent.json"});
  writeText(d / "broken.json", "{\"units\": \"cm\",\n \"measurements\": {\"waist_circ\": 65,}}\n");
  expectRefused(draftSkirt(d / "broken.json"), {d / "broken.json", "line 2"});
  writeText(d / "inch.json", R"({"units": "in", "measurements": {"waist_circ": 26}})");
  expectRefused(draftSkirt(d / "inch.json"), {d / "inch.json", "units"});
  writeText(d / "typo.json", R"({"units": "cm", "measurements": {"wiast_circ": 65}})");
  expectRefused(draftSkirt(d / "typo.json"), {d / "typo.json", "wiast_circ"});
  // A skirt body with one value changed (or, given a negative hip, without the hip).
  auto skirtBody = [&](const std::string& name, double waist, double hip, double height) {
    std::string m = "\"waist_circ\": " + std::to_string(waist) + ", \"waist_to_hip_b\": 19, " +
                    "\"height\": " + std::to_string(height);
    if (hip > 0)
      m += ", \"hip_circ\": " + std::to_string(hip);
    writeText(d / name, "{\"units\": \"cm\", \"measurements\": {" + m + "}}");
    return d / name;
  };
  // A measurement the recipe needs is missing: the recipe and the measurement are named.
  expectRefused(draftSkirt(skirtBody("nohip.json", 65, -1, 171)),
                {"skirt_h", "hip_circ", "missing"});
  // Absurd values.
  expectRefused(draftSkirt(skirtBody("negative.json", -65, 90, 171)), {"waist_circ", "negative"});
  expectRefused(draftSkirt(skirtBody("tiny.json", 65, 90, 20)), {"skirt_h", "height", "plausible"});
  expectRefused(draftSkirt(skirtBody("waist.json", 140, 90, 171)), {"waist_circ", "far above"});
  writeText(d / "bad.vit",
            "<?xml version=\"1.0\"?>\n<vit>\n<version>0.3.3</version>\n<unit>cm\n</vit>\n");
  expectRefused(draftSkirt(d / "bad.vit"), {d / "bad.vit", "line"});
  EXPECT_FALSE(std::filesystem::exists(d / "p.json"));
}

TEST(MeasureCli, BadPatternsNameTheFile) {
  const TempDir d("measure_cli");
  expectRefused(runGarmcap("measure"), {"--pattern"});
  expectRefused(runGarmcap("measure --pattern " + (d / "absent.json")), {d / "absent.json"});
  writeText(d / "broken.json", "{\"type\": \"skirt_h\",\n\n \"panels\": [}\n");
  expectRefused(runGarmcap("measure --pattern " + (d / "broken.json")),
                {d / "broken.json", "line 3"});
  writeText(d / "notpattern.json", R"({"units": "cm", "measurements": {"waist_circ": 65}})");
  expectRefused(runGarmcap("measure --pattern " + (d / "notpattern.json")),
                {d / "notpattern.json"});
}

}  // namespace
