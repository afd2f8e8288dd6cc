// Issue 18 item 6: every sleeve length drafts. Cap sleeves (ending at or above the underarm),
// short sleeves whose length is near the cap height, 3/4 and full sleeves, in every recipe
// with a sleeve; the length is measured on the cut panel, the cap on its seams.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

using namespace garmcap::drafts;

namespace {

const std::vector<std::string> kSleeved = {"dress", "blouse", "sweater", "sleeve"};

double lineLength(const Pattern& p, const std::string& name) {
  for (const auto& l : p.lines) {
    if (l.name == name)
      return polylineLength(l.points);
  }
  return 0;
}

// Cap height of the recipe's sleeve for this body: from the cap top down to the underarm
// points of the drafted (full) sleeve.
double capHeight(const std::string& type, const Measurements& body) {
  const Pattern p = draftGarment(type, body);
  return p.points.at("sleeve_underarm_front").y() - p.points.at("sleeve_cap_top").y();
}

// Length of the cut sleeve read from the panel alone: the cap top corner (the outline's
// highest point) down to the lowest outline point (the hem).
double panelLength(const Panel& s) {
  double top = s.outline.front().y(), bottom = top;
  for (const auto& v : s.outline) {
    top = std::min(top, v.y());
    bottom = std::max(bottom, v.y());
  }
  return bottom - top;
}

const Panel* sleevePanel(const Pattern& p) {
  for (const auto& x : p.panels) {
    if (x.name == "sleeve")
      return &x;
  }
  return nullptr;
}

}  // namespace

TEST(SleeveLength, EveryLengthDraftsInEveryRecipeWithASleeve) {
  for (const auto& chart : {"korean_women", "italian_women"}) {
    const Measurements body = sizeChart(chart).bodies.front();
    const double arm = body.get("arm_shoulder_tip_to_wrist");
    for (const auto& type : kSleeved) {
      const double h = capHeight(type, body);
      const Pattern full = draftGarment(type, body);
      const double declared = full.design.at("sleeve_cap_ease");
      struct Case {
        std::string what;
        double cm;
      };
      const std::vector<Case> cases = {{"cap, to the underarm", h},
                                       {"cap 8 cm", 8},
                                       {"15 cm", 15},
                                       {"0.05 cm below the cap: cap to the underarm", h + 0.05},
                                       {"short, 0.5 cm below the cap", h + 0.5},
                                       {"short, 1 cm below the cap", h + 1},
                                       {"22 cm", 22},
                                       {"3/4", 0.75 * arm},
                                       {"full", arm}};
      for (const auto& c : cases) {
        SCOPED_TRACE(std::string(chart) + " " + type + " " + c.what + " (" + std::to_string(c.cm) +
                     " cm, cap height " + std::to_string(h) + ")");
        Pattern p;
        ASSERT_NO_THROW(p = draftGarment(type, body, {{"sleeve_length", c.cm / arm}}));
        for (const auto& panel : p.panels) {
          EXPECT_TRUE(isSimplePolygon(panel.outline)) << panel.name;
          for (std::size_t v = 0; v < panel.outline.size(); ++v) {
            const auto& next = panel.outline[(v + 1) % panel.outline.size()];
            EXPECT_GT((panel.outline[v] - next).norm(), 1e-3) << panel.name << " vertex " << v;
          }
        }
        const Panel* s = sleevePanel(p);
        ASSERT_NE(s, nullptr);
        EXPECT_TRUE(isSimplePolygon(s->outline));
        EXPECT_LT(signedArea(s->outline), 0);
        EXPECT_NEAR(panelLength(*s), c.cm, 0.3);
        EXPECT_NEAR(measurePattern(p).at("sleeve_length"), c.cm, 0.3);
        const bool capOnly = c.cm < h + 0.1;
        bool underarm = false;
        double capEase = 0;
        for (const auto& seam : p.seams) {
          const double la = sewnEdgeLength(p.panel(seam.a.panel), seam.a);
          const double lb = sewnEdgeLength(p.panel(seam.b.panel), seam.b);
          EXPECT_NEAR(lb - la, seam.easeCm, 0.2) << seam.name;
          underarm = underarm || seam.name == "sleeve_underarm";
          if (seam.name.rfind("armhole", 0) == 0)
            capEase += seam.easeCm;
        }
        EXPECT_EQ(underarm, !capOnly);
        // DSW: the sleeve and the bodice regions keep their vertex counts for every length.
        ASSERT_EQ(p.regions.size(), full.regions.size());
        for (std::size_t r = 0; r < p.regions.size(); ++r) {
          EXPECT_EQ(p.regions[r].polygon.size(), full.regions[r].polygon.size())
              << p.regions[r].name;
        }
        if (type == "sleeve")
          continue;  // no bodice to sew into
        // The cap eases the recipe's cap ease into the armhole; a cap sleeve the share of it
        // that its part of the cap carries.
        const double kept = lineLength(p, "sleeve_cap_front") + lineLength(p, "sleeve_cap_back");
        const double whole =
            capOnly ? lineLength(p, "sleeve_cap_front_full") + lineLength(p, "sleeve_cap_back_full")
                    : kept;
        ASSERT_GT(whole, 0);
        EXPECT_NEAR(capEase, declared * kept / whole, 0.2);
        EXPECT_NEAR(measurePattern(p).at("sleeve_cap_ease"), declared * kept / whole, 0.2);
        if (!capOnly) {
          EXPECT_NEAR(measurePattern(p).at("sleeve_cap_ease"), declared, 0.2);
        } else {
          EXPECT_LT(kept, whole);
          EXPECT_EQ(measurePattern(p).count("sleeve_biceps_circ"), 0u);
          EXPECT_GT(measurePattern(p).at("sleeve_hem_circ"), 0);
        }
      }
    }
  }
}

TEST(SleeveLength, ACapSleeveHemIsAStraightLineAcrossTheCap) {
  const Measurements body = sizeChart("korean_women").body("55");
  const double arm = body.get("arm_shoulder_tip_to_wrist");
  const Pattern p = draftGarment("dress", body, {{"sleeve_length", 8 / arm}});
  const Point2 hf = p.points.at("sleeve_hem_front"), hb = p.points.at("sleeve_hem_back");
  EXPECT_NEAR(hf.y(), hb.y(), 1e-9);
  EXPECT_NEAR(hf.y() - p.points.at("sleeve_cap_top").y(), 8, 1e-6);
  // The hem is the width of the cap at that level: between the cap curves, above the underarm.
  EXPECT_LT(hf.x(), hb.x());
  EXPECT_LT(hb.x() - hf.x(),
            p.points.at("sleeve_underarm_back").x() - p.points.at("sleeve_underarm_front").x());
  EXPECT_NEAR(measurePattern(p).at("sleeve_hem_circ"), hb.x() - hf.x(), 1e-6);
}

TEST(SleeveLength, AShortSleeveIsTheBlockCutAtItsLength) {
  // Underarm seams shortened, hem as wide as the full sleeve at that level.
  const Measurements body = sizeChart("korean_women").body("55");
  const double arm = body.get("arm_shoulder_tip_to_wrist");
  const Pattern full = draftGarment("dress", body);
  const Pattern shortP = draftGarment("dress", body, {{"sleeve_length", 22 / arm}});
  const Point2 uf = full.points.at("sleeve_underarm_front");
  const Point2 wf = full.points.at("sleeve_hem_front");
  const Point2 sf = shortP.points.at("sleeve_hem_front");
  // The short sleeve's hem corner lies on the full sleeve's underarm seam.
  const Point2 d = wf - uf, q = sf - uf;
  EXPECT_NEAR(d.x() * q.y() - d.y() * q.x(), 0, 1e-6 * d.norm());
  EXPECT_NEAR(sf.y() - shortP.points.at("sleeve_cap_top").y(), 22, 1e-6);
}

TEST(SleeveLength, SleeveCapSleevesGradeAcrossTheChart) {
  // One design (a cap sleeve) drafted for every size: region counts stay the same, so DSW can
  // grade it, even where a size's cap is lower than the sleeve.
  const SizeChart& c = sizeChart("korean_women");
  const Pattern ref = draftGarment("dress", c.bodies.front(), {{"sleeve_length", 0.26}});
  for (const auto& body : c.bodies) {
    const Pattern p = draftGarment("dress", body, {{"sleeve_length", 0.26}});
    ASSERT_EQ(p.regions.size(), ref.regions.size());
    for (std::size_t r = 0; r < p.regions.size(); ++r)
      EXPECT_EQ(p.regions[r].polygon.size(), ref.regions[r].polygon.size());
  }
}

TEST(SleeveLength, TooShortToBeASleeveIsRefusedWithAMessage) {
  const Measurements body = sizeChart("korean_women").body("55");
  try {
    draftGarment("dress", body, {{"sleeve_length", 0.02}});
    FAIL() << "a 1.1 cm sleeve was drafted";
  } catch (const DraftError& e) {
    EXPECT_NE(std::string(e.what()).find("use 0 for sleeveless"), std::string::npos) << e.what();
  }
}
