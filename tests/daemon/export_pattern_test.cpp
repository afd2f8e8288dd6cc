// Pattern exports: DXF structure, RUL deltas, GarmentCode curve fit and stitches, SVG at 1:1,
// tiled PDF rasterised by pdftoppm at true scale.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../exports/export_samples.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/seam_allowance.h"

namespace garmcap::drafts {
namespace {

std::vector<std::pair<int, std::string>> dxfPairs(const std::string& dxf) {
  std::vector<std::pair<int, std::string>> out;
  std::istringstream in(dxf);
  std::string code, value;
  while (std::getline(in, code) && std::getline(in, value)) {
    if (!code.empty() && code.back() == '\r')
      code.pop_back();
    if (!value.empty() && value.back() == '\r')
      value.pop_back();
    out.emplace_back(std::stoi(code), value);
  }
  return out;
}

// The pattern as laid out on paper: each piece's cut line (allowance included).
Pattern withCutLines(Pattern pat) {
  const Pattern net = pat;
  for (auto& p : pat.panels)
    p.outline = cutOutline(p, net);
  return pat;
}

TEST(PatternDxf, BlockPerPieceWithTextAndClosedBoundary) {
  const auto pat = exports_test::skirtPattern(96, 72, 61);
  const auto pairs = dxfPairs(patternDxf(pat, {"SK-1001", "M"}));
  ASSERT_FALSE(pairs.empty());
  EXPECT_EQ(pairs.back(), std::make_pair(0, std::string("EOF")));
  int blocks = 0;
  std::map<std::string, int> closed;
  std::vector<std::string> texts;
  for (size_t i = 0; i + 1 < pairs.size(); ++i) {
    if (pairs[i] == std::make_pair(0, std::string("BLOCK")))
      ++blocks;
    if (pairs[i].first == 1)
      texts.push_back(pairs[i].second);
    // A closed POLYLINE: layer (8), 66, 10, 20, 30, then flag 70 = 1.
    if (pairs[i] == std::make_pair(70, std::string("1")) && i >= 5 && pairs[i - 5].first == 8)
      ++closed[pairs[i - 5].second];
  }
  EXPECT_EQ(blocks, 2);
  EXPECT_EQ(closed["1"], 2) << "cut line (allowance included) per piece";
  EXPECT_EQ(closed["14"], 2) << "sew line per piece";
  for (const char* t : {"Piece Name: skirt_front", "Size: M", "Quantity: 1", "Units: METRIC"})
    EXPECT_NE(std::find(texts.begin(), texts.end(), t), texts.end()) << t;
}

TEST(TurnPoints, CornersSeamEndsDartLegsAndNotchesOnly) {
  const auto pat = exports_test::skirtPattern(96, 72, 61);
  const auto turns = turnPointIndices(pat.panels[0], pat);
  for (int v : {0, 3, 5, 8, 16, 17, 25})
    EXPECT_NE(std::find(turns.begin(), turns.end(), v), turns.end()) << v;
  for (int v : {1, 2, 11, 20})
    EXPECT_EQ(std::find(turns.begin(), turns.end(), v), turns.end()) << v;
}

TEST(GradeRules, SampleIsZeroAndDeltasMatchTheSizes) {
  const auto run = exports_test::skirtRun();
  const std::string rul = gradeRuleTable(run);
  EXPECT_NE(rul.find("SIZE LIST: S M L XL"), std::string::npos);
  EXPECT_NE(rul.find("SAMPLE SIZE: M"), std::string::npos);
  EXPECT_NE(rul.find("NUMBER OF SIZES: 4"), std::string::npos);
  // Rule 1 = first turn point of skirt_front = vertex 0 (centre front waist, fixed at 0,0):
  // every delta 0. Check one moving rule: the hem side corner (vertex 17) of skirt_front.
  const auto turns = turnPointIndices(run.patterns[1].panels[0], run.patterns[1]);
  const int rule = static_cast<int>(std::find(turns.begin(), turns.end(), 17) - turns.begin()) + 1;
  const std::string key = "RULE: DELTA " + std::to_string(rule) + "\r\n";
  const size_t at = rul.find(key);
  ASSERT_NE(at, std::string::npos);
  std::istringstream line(
      rul.substr(at + key.size(), rul.find("\r\n", at + key.size()) - at - key.size()));
  std::string pair;
  for (size_t s = 0; s < 4; ++s) {
    ASSERT_TRUE(line >> pair);
    double dx = 0, dy = 0;
    ASSERT_EQ(std::sscanf(pair.c_str(), "%lf,%lf", &dx, &dy), 2) << pair;
    const Point2 d = run.patterns[s].panels[0].outline[17] - run.patterns[1].panels[0].outline[17];
    EXPECT_NEAR(dx, d.x() * 10, 1e-3);
    EXPECT_NEAR(dy, -d.y() * 10, 1e-3);
    if (s == 1) {
      EXPECT_EQ(pair, "0.000,0.000");
    }
  }
  // Every turn point of both panels has a rule, and the table ends.
  size_t n = 0;
  for (const auto& p : run.patterns[1].panels)
    n += turnPointIndices(p, run.patterns[1]).size();
  EXPECT_NE(rul.find("RULE: DELTA " + std::to_string(n) + "\r\n"), std::string::npos);
  EXPECT_EQ(rul.find("RULE: DELTA " + std::to_string(n + 1) + "\r\n"), std::string::npos);
  EXPECT_EQ(rul.substr(rul.size() - 5), "END\r\n");
}

TEST(GradedRun, RefusesSizesThatDoNotCorrespond) {
  auto run = exports_test::skirtRun();
  run.sampleSize = "XXL";
  EXPECT_THROW(checkGradedRun(run), PatternExportError);
  run = exports_test::skirtRun();
  run.patterns[2].panels[0].outline.pop_back();
  EXPECT_THROW(gradedDxf(run), DxfExportError);
}

TEST(GradedDxf, EverySizeOfEveryPieceAndSampleMarked) {
  const auto pairs = dxfPairs(gradedDxf(exports_test::skirtRun()));
  std::vector<std::string> blocks, texts;
  for (size_t i = 0; i + 1 < pairs.size(); ++i) {
    if (pairs[i] == std::make_pair(0, std::string("BLOCK")))
      blocks.push_back(pairs[i + 2].second);
    if (pairs[i].first == 1)
      texts.push_back(pairs[i].second);
  }
  EXPECT_EQ(blocks.size(), 8u);
  EXPECT_NE(std::find(blocks.begin(), blocks.end(), "skirt_back_XL"), blocks.end());
  EXPECT_EQ(std::count(texts.begin(), texts.end(), "Sample Size: M"), 3);  // 2 pieces + style
  EXPECT_NE(std::find(texts.begin(), texts.end(), "# 1"), texts.end());
}

// The hand-built skirt is drawn clockwise on paper (against the drafts convention) and both
// pieces are cut on the fold: GarmentCode still gets counter-clockwise, unfolded loops, the side
// seam stitched on both halves. Its dart's apex is not an outline vertex (a marked dart, not
// cut out), so nothing is stitched within a piece.
// (tests/drafts/export_garmentcode_test.cpp rebuilds every drafted type from the JSON.)
TEST(GarmentCode, ClockwiseFoldPiecesUnfoldedWithDartsAndBothSideSeams) {
  const auto pat = exports_test::skirtPattern(96, 72, 61);
  const auto spec = nlohmann::json::parse(garmentCodeJson(pat, {"SK-1001", "M"}));
  EXPECT_EQ(spec["properties"]["units_in_meter"], 100);
  EXPECT_EQ(spec["properties"]["curvature_coords"], "relative");
  const auto& panels = spec["pattern"]["panels"];
  ASSERT_EQ(panels.size(), 2u);
  for (const auto& [name, p] : panels.items()) {
    const auto& v = p["vertices"];
    double area = 0, minX = 1e9, maxX = -1e9;
    for (size_t i = 0; i < v.size(); ++i) {
      const auto& a = v[i];
      const auto& b = v[(i + 1) % v.size()];
      area += a[0].get<double>() * b[1].get<double>() - b[0].get<double>() * a[1].get<double>();
      minX = std::min(minX, a[0].get<double>());
      maxX = std::max(maxX, a[0].get<double>());
    }
    EXPECT_GT(area, 0) << name << " must be counter-clockwise";
    EXPECT_EQ(p["edges"].size(), v.size());
    // Unfolded: twice the half width (hip/4 + 1 + 2 cm flare at the hem).
    EXPECT_NEAR(maxX - minX, 2 * (96 / 4.0 + 1 + 2), 1e-6) << name;
  }
  int between = 0, within = 0;
  for (const auto& st : spec["pattern"]["stitches"])
    (st[0]["panel"] == st[1]["panel"] ? within : between) += 1;
  EXPECT_GE(between, 2) << "side seam on both halves";
  EXPECT_EQ(within, 0);
}

TEST(PatternSvg, OneToOneInMillimetres) {
  const auto pat = exports_test::skirtPattern(96, 72, 61);
  const std::string svg = patternSvg(pat, {"SK-1001", "M"});
  const Layout lay = layoutPanels(withCutLines(pat), 2.0, 160.0);
  char want[64];
  std::snprintf(want, sizeof want, "width=\"%.2fmm\"", lay.widthCm * 10);
  EXPECT_NE(svg.find(want), std::string::npos) << svg.substr(0, 300);
  const auto dir =
      std::filesystem::temp_directory_path() / ("garmcap_svg_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "p.svg") << svg;
  // librsvg parses it (96 px per inch: the width in px is mm * 96 / 25.4).
  ASSERT_EQ(std::system(("rsvg-convert -o '" + (dir / "p.png").string() + "' '" +
                         (dir / "p.svg").string() + "'")
                            .c_str()),
            0);
  std::ifstream png(dir / "p.png", std::ios::binary);
  unsigned char hdr[24];
  png.read(reinterpret_cast<char*>(hdr), 24);
  const int w = (hdr[16] << 24) | (hdr[17] << 16) | (hdr[18] << 8) | hdr[19];
  EXPECT_NEAR(w, lay.widthCm * 10 * 96 / 25.4, 1.0);
  std::filesystem::remove_all(dir);
}

// Reads a binary PGM written by pdftoppm -gray.
struct Gray {
  int w = 0, h = 0;
  std::string px;
  unsigned char at(int x, int y) const {
    return static_cast<unsigned char>(px[static_cast<size_t>(y * w + x)]);
  }
};
Gray readPgm(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::string magic;
  int maxv = 0;
  Gray g;
  f >> magic >> g.w >> g.h >> maxv;
  f.get();
  g.px.resize(static_cast<size_t>(g.w * g.h));
  f.read(g.px.data(), static_cast<std::streamsize>(g.px.size()));
  return g;
}

TEST(PatternPdf, TiledA4AtTrueScale) {
  const auto pat = exports_test::skirtPattern(96, 72, 61);
  const std::string pdf = patternPdfA4(pat, {"SK-1001", "M"});
  const auto dir =
      std::filesystem::temp_directory_path() / ("garmcap_pdf_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "p.pdf", std::ios::binary) << pdf;
  // pdfinfo: A4 pages, as many as the layout needs.
  const std::string info = (dir / "info.txt").string();
  ASSERT_EQ(
      std::system(("pdfinfo '" + (dir / "p.pdf").string() + "' > '" + info + "' 2>&1").c_str()), 0);
  std::ifstream in(info);
  std::string all((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(all.find("595.276 x 841.89 pts (A4)"), std::string::npos) << all;
  // Tiles of 19 x 27.7 cm overlapping by 1 cm over rows up to 91 cm wide, the 14 cm test
  // square block on top; tiles without ink are left out (tests/drafts/pdf_tiles_check.py
  // checks that from the raster).
  const Layout lay = layoutPanels(withCutLines(pat), 2.0, 19.0 + 4 * 18.0);
  const int cols = static_cast<int>(std::ceil((lay.widthCm - 1.0) / 18.0));
  const int rows = static_cast<int>(std::ceil((lay.heightCm + 14.0 - 1.0) / 26.7));
  const size_t pagesAt = all.find("Pages:");
  ASSERT_NE(pagesAt, std::string::npos);
  EXPECT_GE(std::stoi(all.substr(pagesAt + 6)), 1) << all;
  EXPECT_LE(std::stoi(all.substr(pagesAt + 6)), rows * cols) << all;
  EXPECT_EQ(all.find("Syntax Error"), std::string::npos) << all;
  // Page 1 at 254 dpi: 100 px per cm. The test square's outer edges are 10 cm apart.
  ASSERT_EQ(std::system(("pdftoppm -gray -r 254 -f 1 -l 1 '" + (dir / "p.pdf").string() + "' '" +
                         (dir / "pg").string() + "'")
                            .c_str()),
            0);
  std::filesystem::path pgm;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".pgm")
      pgm = e.path();
  const Gray g = readPgm(pgm);
  EXPECT_NEAR(g.w, 2100, 1);
  EXPECT_NEAR(g.h, 2970, 1);
  // Row through the square's middle: sheet y = 7 cm, tile origin at the 1 cm margin.
  const int y = 100 + 700;
  std::vector<int> dark;
  for (int x = 0; x < g.w; ++x)
    if (g.at(x, y) < 128)
      dark.push_back(x);
  ASSERT_GE(dark.size(), 2u);
  // Left edge of the square at 1 + 2 = 3 cm; find the first dark run after x=250 and the last
  // dark pixel before 1400 (the square spans 300..1300 px).
  int left = -1, right = -1;
  for (int x : dark)
    if (x > 250 && x < 400 && left < 0)
      left = x;
  for (int x : dark)
    if (x > 1200 && x < 1400)
      right = x;
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  // Stroke 0.8 pt = 2.8 px wide centred on the edge: outer-to-outer is 1000 + stroke width.
  EXPECT_NEAR(right - left, 1000 + 2.8, 2.5) << "left " << left << " right " << right;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace garmcap::drafts
