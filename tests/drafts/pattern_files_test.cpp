// The SVG and PDF pattern files of every garment type: each piece drawn with its cut line
// (allowance included) and its sew line, the allowance stated, and a "place on fold" bracket on
// every piece cut on the fold, its ends on the fold line. Read back from the file text.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::drafts {
namespace {

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

// The points="x,y x,y ..." of every element with class `cls` in `svg`, in mm.
std::vector<Polyline> pointsOfClass(const std::string& svg, const std::string& cls) {
  std::vector<Polyline> out;
  const std::string key = "class=\"" + cls + "\" points=\"";
  for (size_t at = svg.find(key); at != std::string::npos; at = svg.find(key, at + 1)) {
    const size_t from = at + key.size();
    std::istringstream in(svg.substr(from, svg.find('"', from) - from));
    Polyline pl;
    double x = 0, y = 0;
    char comma = 0;
    while (in >> x >> comma >> y)
      pl.emplace_back(x, y);
    out.push_back(pl);
  }
  return out;
}

// One <g id="piece">...</g> group of the SVG.
std::string group(const std::string& svg, const std::string& piece) {
  const size_t at = svg.find("<g id=\"" + piece + "\">");
  if (at == std::string::npos)
    return {};
  return svg.substr(at, svg.find("</g>", at) - at);
}

TEST(PatternFiles, SvgDrawsCutAndSewLinesAndFoldBrackets) {
  for (const auto& type : garmentTypes()) {
    const Pattern pat = draftGarment(type.name, sizeChart("korean_women").body("66"));
    const std::string svg = patternSvg(pat, {"T-1", "66"});
    EXPECT_NE(svg.find("seam allowance 10.0 mm included, hem 30.0 mm, none on fold"),
              std::string::npos)
        << type.name;
    int folds = 0;
    for (const auto& panel : pat.panels) {
      SCOPED_TRACE(type.name + "/" + panel.name);
      const std::string g = group(svg, panel.name);
      ASSERT_FALSE(g.empty());
      const auto cut = pointsOfClass(g, "cut"), sew = pointsOfClass(g, "sew");
      ASSERT_EQ(cut.size(), 1u);
      ASSERT_EQ(sew.size(), 1u);
      EXPECT_EQ(sew[0].size(), panel.outline.size());
      // The cut line lies outside the sew line: its bounding box is larger on every side
      // except a fold's (where it is the same).
      auto box = [](const Polyline& pl) {
        Point2 lo(1e300, 1e300), hi(-1e300, -1e300);
        for (const auto& p : pl) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
        return std::pair{lo, hi};
      };
      const auto [cutLo, cutHi] = box(cut[0]);
      const auto [sewLo, sewHi] = box(sew[0]);
      EXPECT_LE(cutLo.x(), sewLo.x() + 1e-6);
      EXPECT_GE(cutHi.x(), sewHi.x() - 1e-6);
      EXPECT_NEAR(cutLo.y(), sewLo.y() - 10.0, 5.0) << "1 cm above the top edge (mm)";
      EXPECT_GT(cutHi.y(), sewHi.y() + 9.9) << "hem or seam below";
      const auto bracket = pointsOfClass(g, "fold");
      if (!foldEdge(panel, pat)) {
        EXPECT_TRUE(bracket.empty());
        continue;
      }
      ++folds;
      ASSERT_EQ(bracket.size(), 3u) << "bracket and two arrowheads";
      ASSERT_EQ(bracket[0].size(), 4u);
      const double foldX = bracket[0][0].x();
      EXPECT_NEAR(bracket[0][3].x(), foldX, 1e-6);
      EXPECT_TRUE(std::abs(foldX - sewLo.x()) < 0.01 || std::abs(foldX - sewHi.x()) < 0.01)
          << "bracket ends on the piece's centre edge";
      EXPECT_NEAR(std::abs(bracket[0][1].x() - foldX), 20.0, 0.01) << "2 cm inside the fold";
      for (size_t k = 1; k < 3; ++k)
        EXPECT_NEAR(bracket[k][1].x(), foldX, 1e-6) << "arrow tips on the fold";
      EXPECT_NE(g.find(">PLACE ON FOLD</text>"), std::string::npos);
    }
    EXPECT_EQ(countOf(svg, ">PLACE ON FOLD</text>"), folds) << type.name;
  }
}

TEST(PatternFiles, PdfStatesTheAllowanceAndMarksEveryFold) {
  for (const char* type : {"dress", "skirt_a", "pants"}) {
    const Pattern pat = draftGarment(type, sizeChart("korean_women").body("66"));
    const std::string pdf = patternPdfA4(pat, {"T-1", "66"});
    int folds = 0;
    for (const auto& panel : pat.panels)
      folds += foldEdge(panel, pat) ? 1 : 0;
    const int pages = countOf(pdf, "/Type /Page ");
    ASSERT_GT(pages, 0);
    // The sheet's drawing is repeated on every page (each clipped to its tile).
    EXPECT_EQ(countOf(pdf, "(PLACE ON FOLD) Tj"), folds * pages) << type;
    EXPECT_EQ(countOf(pdf,
                      "(Cut on the solid line: seam allowance 10.0 mm included, hem 30.0 mm, "
                      "none on fold.) Tj"),
              pages)
        << type;
    EXPECT_EQ(countOf(pdf, "(Sew on the dashed line (the net seam line).) Tj"), 0)
        << "parentheses are escaped in PDF strings";
    EXPECT_EQ(countOf(pdf, "(Sew on the dashed line \\(the net seam line\\).) Tj"), pages);
  }
}

// Group code / value pairs of an ASCII DXF.
std::vector<std::pair<int, std::string>> dxfPairs(const std::string& dxf) {
  std::vector<std::pair<int, std::string>> out;
  std::istringstream in(dxf);
  std::string code, value;
  auto trim = [](std::string s) {
    while (!s.empty() && (s.back() == '\r' || s.back() == ' '))
      s.pop_back();
    return s.substr(std::min(s.find_first_not_of(' '), s.size()));
  };
  while (std::getline(in, code) && std::getline(in, value))
    out.emplace_back(std::stoi(trim(code)), trim(value));
  return out;
}

TEST(PatternFiles, DxfVersionAndStandardAgreeWithTheRul) {
  const Pattern pat = draftGarment("skirt_a", sizeChart("korean_women").body("66"));
  const GradedRun run{"T-1", {"66", "77"}, "66", {pat, pat}};
  for (const std::string& dxf : {patternDxf(pat, {"T-1", "66"}), gradedDxf(run)}) {
    const auto pairs = dxfPairs(dxf);
    const auto ver =
        std::find(pairs.begin(), pairs.end(), std::pair<int, std::string>{9, "$ACADVER"});
    ASSERT_NE(ver, pairs.end());
    EXPECT_EQ(*(ver + 1), (std::pair<int, std::string>{1, "AC1009"})) << "R12";
    EXPECT_NE(
        std::find(pairs.begin(), pairs.end(), std::pair<int, std::string>{1, kAstmVersionLine}),
        pairs.end())
        << "the DXF names the standard the RUL names";
  }
  const std::string rul = gradeRuleTable(run);
  EXPECT_EQ(rul.substr(0, rul.find("\r\n")), kAstmVersionLine);
}

}  // namespace
}  // namespace garmcap::drafts
