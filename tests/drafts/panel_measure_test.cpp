#include "garmcap/drafts/panel_measure.h"

#include <gtest/gtest.h>

using namespace garmcap::drafts;

namespace {

// A 20 x 30 rectangle (counter-clockwise on paper) with a 4 cm wide, 10 cm deep dart in its
// top edge centred at x = 10.
Panel dartedRectangle() {
  Panel p;
  p.name = "test";
  p.outline = {{0, 0}, {0, 30}, {20, 30}, {20, 0}, {12, 0}, {10, 10}, {8, 0}};
  p.darts.push_back(Dart{"d", {10, 10}, {12, 0}, {8, 0}});
  return p;
}

}  // namespace

TEST(PanelMeasure, SewnEdgeLeavesOutTheDart) {
  const Panel p = dartedRectangle();
  // Top edge from (20,0) (index 3) to (0,0) (index 0): 20 cm minus the 4 cm dart opening.
  EXPECT_NEAR(sewnEdgeLength(p, EdgeRef{"test", 3, 0}), 16.0, 1e-12);
  // Right side: no dart.
  EXPECT_NEAR(sewnEdgeLength(p, EdgeRef{"test", 2, 3}), 30.0, 1e-12);
  EXPECT_THROW(sewnEdgeLength(p, EdgeRef{"test", 0, 9}), std::out_of_range);
}

TEST(PanelMeasure, WidthAtALevelExcludesOpenDarts) {
  const Panel p = dartedRectangle();
  EXPECT_NEAR(panelWidthAtLevel(p, 5.0), 18.0, 1e-9);   // dart 2 cm open half way
  EXPECT_NEAR(panelWidthAtLevel(p, 20.0), 20.0, 1e-9);  // below the apex
  EXPECT_NEAR(panelWidthAtLevel(p, 40.0), 0.0, 1e-12);  // outside
}

TEST(PanelMeasure, NearestVertexWithinTolerance) {
  const Panel p = dartedRectangle();
  EXPECT_EQ(nearestOutlineVertex(p, {10.2, 9.9}, 0.5), 5);
  EXPECT_FALSE(nearestOutlineVertex(p, {5, 5}, 0.5).has_value());
}

TEST(PanelMeasure, GirthCountsPiecesAndFold) {
  Pattern pat;
  pat.type = "skirt_high_waist";  // uses level_waist chords and top/skirt landmarks
  Panel a;
  a.name = "skirt_back";
  a.outline = {{0, 0}, {0, 50}, {20, 50}, {20, 0}};
  a.cutCount = 2;
  Panel b = a;
  b.name = "skirt_front";
  b.outline = {{20, 0}, {20, 50}, {45, 50}, {45, 0}};
  b.cutCount = 1;
  b.cutOnFold = true;
  pat.panels = {a, b};
  pat.points = {{"level_waist", {0, 5}},           {"level_hip", {0, 20}},
                {"skirt_top_cb", {0, 0}},          {"skirt_top_side_back", {20, 0}},
                {"skirt_top_side_front", {20, 0}}, {"skirt_top_cf", {45, 0}},
                {"skirt_hem_cf", {45, 50}},        {"skirt_hem_cb", {0, 50}},
                {"skirt_hem_side_back", {20, 50}}, {"skirt_hem_side_front", {20, 50}}};
  const auto m = measurePattern(pat);
  EXPECT_NEAR(m.at("waist_circ"), 20 * 2 + 25 * 2, 1e-6);
  EXPECT_NEAR(m.at("hip_circ"), 90, 1e-6);
  EXPECT_NEAR(m.at("top_circ"), 90, 1e-6);
  EXPECT_NEAR(m.at("skirt_length"), 45, 1e-6);
}

TEST(PanelMeasure, MissingLandmarkIsNamed) {
  Pattern pat;
  pat.type = "skirt_h";
  try {
    measurePattern(pat);
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("skirt_h"), std::string::npos) << e.what();
  }
}
