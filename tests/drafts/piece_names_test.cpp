// Piece names a person reads (issue 18): the pattern files label pieces "Bodice front", "Skirt
// back", "Sleeve" where they showed code ids, and keep the ids where files use them as keys.
#include <gtest/gtest.h>

#include <string>

#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/drafts/svg.h"

namespace {

namespace gd = garmcap::drafts;

TEST(PieceNames, TitlesOfEveryPanel) {
  EXPECT_EQ(gd::pieceTitle("bodice_front"), "Bodice front");
  EXPECT_EQ(gd::pieceTitle("skirt_back"), "Skirt back");
  EXPECT_EQ(gd::pieceTitle("sleeve"), "Sleeve");
  EXPECT_EQ(gd::pieceTitle("pants_front"), "Trousers front");
  EXPECT_EQ(gd::pieceTitle("body_back"), "Back");
  // Every panel of every type gets a title without underscores, starting with a capital.
  for (const auto& t : gd::garmentTypes()) {
    const gd::Pattern p = gd::draftGarment(t.name, gd::sizeChart("korean_women").body("66"));
    for (const auto& panel : p.panels) {
      const std::string title = gd::pieceTitle(panel.name);
      EXPECT_EQ(title.find('_'), std::string::npos) << t.name << " " << panel.name;
      EXPECT_TRUE(title[0] >= 'A' && title[0] <= 'Z') << t.name << " " << panel.name;
    }
  }
}

TEST(PieceNames, FilesLabelPiecesByTitleAndKeepIdsAsKeys) {
  const gd::Pattern p = gd::draftGarment("dress", gd::sizeChart("korean_women").body("66"));
  const gd::PieceText text{"STYLE1", "66"};
  const std::string svg = gd::patternSvg(p, text);
  const std::string pdf = gd::patternPdf(p, text, gd::parsePaper("a0"));
  const std::string dxf = gd::patternDxf(p, text);
  const std::string draftSvg = gd::patternToSvg(p, {});
  for (const auto& panel : p.panels) {
    const std::string title = gd::pieceTitle(panel.name);
    EXPECT_NE(svg.find(">" + title + "</text>"), std::string::npos) << title;
    EXPECT_EQ(svg.find(">" + panel.name + "</text>"), std::string::npos) << panel.name;
    EXPECT_NE(svg.find("<g id=\"" + panel.name + "\">"), std::string::npos) << panel.name;
    EXPECT_NE(pdf.find("(" + title + ") Tj"), std::string::npos) << title;
    EXPECT_EQ(pdf.find("(" + panel.name + ") Tj"), std::string::npos) << panel.name;
    EXPECT_NE(draftSvg.find(">" + title + "</text>"), std::string::npos) << title;
    // The AAMA piece name is the key a grading CAD files the piece under: the id.
    EXPECT_NE(dxf.find("Piece Name: " + panel.name), std::string::npos) << panel.name;
  }
  EXPECT_NE(svg.find(">Bodice front</text>"), std::string::npos);
  EXPECT_NE(svg.find(">Skirt back</text>"), std::string::npos);
  EXPECT_NE(svg.find(">Sleeve</text>"), std::string::npos);
}

}  // namespace
