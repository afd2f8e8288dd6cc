#include "garmcap/drafts/pattern_io.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

using namespace garmcap::drafts;

namespace {

Pattern dress() {
  return draftGarment("dress", sizeChart("korean_women").body("55"));
}

std::string errorOf(const std::string& text) {
  try {
    patternFromJson(text, "p.json");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PatternJson, RoundTripKeepsEverything) {
  const Pattern p = dress();
  const Pattern q = patternFromJson(patternToJson(p), "mem");
  EXPECT_EQ(q.type, p.type);
  EXPECT_EQ(q.measurements, p.measurements);
  EXPECT_EQ(q.design, p.design);
  ASSERT_EQ(q.points.size(), p.points.size());
  ASSERT_EQ(q.panels.size(), p.panels.size());
  ASSERT_EQ(q.seams.size(), p.seams.size());
  ASSERT_EQ(q.regions.size(), p.regions.size());
  for (std::size_t i = 0; i < p.panels.size(); ++i) {
    EXPECT_EQ(q.panels[i].name, p.panels[i].name);
    ASSERT_EQ(q.panels[i].outline.size(), p.panels[i].outline.size());
    for (std::size_t k = 0; k < p.panels[i].outline.size(); ++k) {
      EXPECT_EQ(q.panels[i].outline[k], p.panels[i].outline[k]);  // doubles printed exactly
    }
    EXPECT_EQ(q.panels[i].darts.size(), p.panels[i].darts.size());
    EXPECT_EQ(q.panels[i].cutCount, p.panels[i].cutCount);
    EXPECT_EQ(q.panels[i].cutOnFold, p.panels[i].cutOnFold);
    EXPECT_EQ(q.panels[i].draftRegions, p.panels[i].draftRegions);
  }
  EXPECT_EQ(patternToJson(q), patternToJson(p));
}

TEST(PatternJson, FileRoundTrip) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("garmcap_pattern_" + std::to_string(::getpid()) + ".json");
  writePatternJson(path, dress());
  EXPECT_EQ(readPatternJson(path).panels.size(), dress().panels.size());
  std::filesystem::remove(path);
}

TEST(PatternJson, StrictReaderNamesFileAndField) {
  auto j = patternToJsonValue(dress());
  auto bad = j;
  bad["panels"][0]["colour"] = "red";
  EXPECT_NE(errorOf(bad.dump()).find("p.json: /panels/0: unknown field 'colour'"),
            std::string::npos)
      << errorOf(bad.dump());
  bad = j;
  bad["panels"][1].erase("cut_count");
  EXPECT_NE(errorOf(bad.dump()).find("cut_count"), std::string::npos);
  EXPECT_NE(errorOf(bad.dump()).find("p.json"), std::string::npos);
  bad = j;
  bad["panels"][0]["outline"][2] = nlohmann::json::array({1.0});
  EXPECT_NE(errorOf(bad.dump()).find("/panels/0/outline/2"), std::string::npos)
      << errorOf(bad.dump());
  bad = j;
  bad["seams"][0]["a"]["from"] = 100000;
  EXPECT_NE(errorOf(bad.dump()).find("out of range"), std::string::npos);
  bad = j;
  bad["seams"][0]["b"]["panel"] = "nope";
  EXPECT_NE(errorOf(bad.dump()).find("no panel named 'nope'"), std::string::npos);
  bad = j;
  bad["units"] = "mm";
  EXPECT_NE(errorOf(bad.dump()).find("/units"), std::string::npos);
  bad = j;
  bad["version"] = 2;
  EXPECT_NE(errorOf(bad.dump()).find("unsupported version"), std::string::npos);
  bad = j;
  bad["design"]["ease_bust"] = "lots";
  EXPECT_NE(errorOf(bad.dump()).find("/design/ease_bust"), std::string::npos);
  EXPECT_NE(errorOf("{\"format\": ").find("line 1"), std::string::npos) << errorOf("{\"format\": ");
}
