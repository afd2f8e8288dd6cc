// Strict reading of the `garmcap coords` point files, and the size guide of a size run.
#include "garmcap/dsw/points_io.h"

#include <gtest/gtest.h>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_run.h"

namespace garmcap::dsw {
namespace {

Points parse(const std::string& text, const std::string& key = "polygon") {
  return pointsFromJson(drafts::parseJson(text, "poly.json"), key, "poly.json");
}

std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const drafts::ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(PointsIo, ReadsPointsStrictly) {
  const Points p = parse(R"({"polygon": [[0, 0], [2.5, 0], [1, 3]]})");
  ASSERT_EQ(p.rows(), 3);
  EXPECT_EQ(p(1, 0), 2.5);
  EXPECT_EQ(p(2, 1), 3.0);
  EXPECT_NE(errorOf(R"({"points": [[0, 0]]})").find("unknown field 'points'"), std::string::npos);
  EXPECT_NE(errorOf(R"({})").find("missing field 'polygon'"), std::string::npos);
  EXPECT_NE(errorOf(R"({"polygon": [[0, 0], [1]]})").find("polygon[1]"), std::string::npos);
  EXPECT_NE(errorOf(R"({"polygon": [[0, "a"]]})").find("polygon[0]"), std::string::npos);
  // JSON has no NaN or infinity; an overflowing number is refused by the parser, naming the file.
  EXPECT_NE(errorOf(R"({"polygon": [[0, 1e999]]})").find("poly.json"), std::string::npos);
  EXPECT_NE(errorOf(R"({"polygon": 3})").find("array"), std::string::npos);
  EXPECT_NE(errorOf(R"([1, 2])").find("object"), std::string::npos);
}

TEST(SizeRun, EveryChartSizeGradedWithAGuide) {
  const drafts::Pattern src =
      drafts::readPatternJson(std::string(GARMCAP_TEST_DATA_DIR) + "/designs/dress_55.json");
  const drafts::SizeChart& chart = drafts::sizeChart("korean_women");
  auto run = gradeSizeRun(src, chart);
  ASSERT_TRUE(run.ok()) << run.error().message;
  ASSERT_EQ(run->sizes, chart.sizes);
  for (std::size_t i = 1; i < run->sizes.size(); ++i)
    EXPECT_GT(run->garment[i].at("bust_circ"), run->garment[i - 1].at("bust_circ"));
  EXPECT_TRUE(run->skipped.empty());
  EXPECT_TRUE(run->garment[0].count("waist_circ"));
  EXPECT_EQ(run->body[0].at("bust_circ"), chart.bodies[0].get("bust_circ"));
}

}  // namespace
}  // namespace garmcap::dsw
