#include "garmcap/drafts/svg.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <regex>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

using namespace garmcap::drafts;

TEST(Svg, TrueScaleWidthHeightInCmMatchTheViewBox) {
  const Pattern p = draftGarment("skirt_h", sizeChart("korean_women").body("55"));
  const std::string svg = patternToSvg(p);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      svg, m,
      std::regex(
          R"re(width="([0-9.]+)cm" height="([0-9.]+)cm" viewBox="([-0-9.]+) ([-0-9.]+) ([0-9.]+) ([0-9.]+)")re")));
  EXPECT_DOUBLE_EQ(std::stod(m[1]), std::stod(m[5]));  // 1 user unit = 1 cm
  EXPECT_DOUBLE_EQ(std::stod(m[2]), std::stod(m[6]));
  // The drawing is as wide as the skirt's cut line: (hip + ease)/2, the 1 cm side-seam allowance
  // (none on the centre fold), plus margins.
  EXPECT_NEAR(std::stod(m[5]), (90.0 + 4) / 2 + 1.0 + 2 * 3.0, 0.5);
  EXPECT_NE(svg.find("class=\"cut-line\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"sew-line\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"legend\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"draft-construction\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"draft-contours\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"panel-skirt_front\""), std::string::npos);
  EXPECT_NE(svg.find("marker-end=\"url(#arrow)\""), std::string::npos);  // grainline
  EXPECT_NE(svg.find("cut 1 on fold"), std::string::npos);
}

TEST(Svg, EveryTypeRendersWithRsvg) {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "rsvg-convert not installed (station.sh installs librsvg2-bin)";
  }
  const auto dir =
      std::filesystem::temp_directory_path() / ("garmcap_svg_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const auto& t : garmentTypes()) {
    const auto svg = dir / (t.name + ".svg");
    writePatternSvg(svg, draftGarment(t.name, sizeChart("korean_women").body("55")));
    const std::string cmd = "rsvg-convert -w 200 '" + svg.string() + "' -o '" +
                            (dir / (t.name + ".png")).string() + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << t.name;
    EXPECT_GT(std::filesystem::file_size(dir / (t.name + ".png")), 1000u) << t.name;
  }
  std::filesystem::remove_all(dir);
}
