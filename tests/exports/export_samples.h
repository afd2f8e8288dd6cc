#pragma once
// Hand-built sample patterns and catalog items for the export tests (no recipe needed): a
// two-panel skirt with curved waist and hem, a dart, notches, a grainline, an internal line and
// side seams; graded sizes keep the vertex count and order, as DSW does.

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "garmcap/daemon/export_shop.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/pattern.h"

namespace garmcap::exports_test {

using drafts::Point2;

inline drafts::Panel skirtPanel(const std::string& name, double hipCm, double waistCm,
                                double lengthCm, double waistDropCm) {
  drafts::Panel p;
  p.name = name;
  const double hw = hipCm / 4 + 1.0, ww = waistCm / 4 + 2.0, hipDepth = 18.0;
  // Waist: centre (0, waistDrop) curving up to the side (ww, -1.2), 9 points (index 0..8).
  for (int i = 0; i <= 8; ++i) {
    double t = i / 8.0;
    p.outline.emplace_back(ww * t, waistDropCm * (1 - t * t) - 1.2 * t * t);
  }
  // Side seam: waist to hip, a curve, 8 more points (index 9..16).
  for (int i = 1; i <= 8; ++i) {
    double t = i / 8.0;
    p.outline.emplace_back(ww + (hw - ww) * std::sin(t * M_PI / 2), -1.2 + (hipDepth + 1.2) * t);
  }
  // Hip to hem side, straight, flaring 2 cm (index 17).
  p.outline.emplace_back(hw + 2.0, lengthCm);
  // Hem: curving down to the centre, 8 points (index 18..25).
  for (int i = 1; i <= 8; ++i) {
    double t = i / 8.0;
    p.outline.emplace_back((hw + 2.0) * (1 - t), lengthCm + 0.8 * t * t);
  }
  // Centre line goes straight back up to index 0.
  p.darts.push_back({"waist_dart", Point2(ww / 2, 10.0), p.outline[3], p.outline[5]});
  p.notches.push_back({"hip", p.outline[16]});
  p.notches.push_back({"side_mid", (p.outline[16] + p.outline[17]) / 2});
  p.grainline = {Point2(hw / 2, 6.0), Point2(hw / 2, lengthCm - 6.0)};
  p.internalLines.push_back({"hip_line", {Point2(0, hipDepth), Point2(hw, hipDepth)}, false});
  p.cutCount = 1;
  p.cutOnFold = true;
  return p;
}

inline drafts::Pattern skirtPattern(double hipCm, double waistCm, double lengthCm) {
  drafts::Pattern pat;
  pat.type = "skirt";
  pat.measurements.set("hip_circ", hipCm);
  pat.measurements.set("waist_circ", waistCm);
  pat.panels.push_back(skirtPanel("skirt_front", hipCm, waistCm, lengthCm, 0.0));
  pat.panels.push_back(skirtPanel("skirt_back", hipCm, waistCm, lengthCm, 1.0));
  pat.seams.push_back({"side_seam", {"skirt_front", 8, 17}, {"skirt_back", 8, 17}, 0.0});
  return pat;
}

inline drafts::GradedRun skirtRun() {
  drafts::GradedRun run;
  run.style = "SK-1001";
  run.sizes = {"S", "M", "L", "XL"};
  run.sampleSize = "M";
  for (int i = 0; i < 4; ++i)
    run.patterns.push_back(skirtPattern(92.0 + 5.0 * (i - 1), 70.0 + 5.0 * (i - 1), 60.0 + i));
  return run;
}

/// A size guide over S, M, L whose row `item` is the piece (chart "test").
inline dsw::SizeGuide sampleGuide(const std::vector<std::map<std::string, double>>& rows,
                                  std::size_t item) {
  dsw::SizeGuide g;
  g.type = "skirt";
  g.chart = "test";
  const std::vector<std::string> sizes = {"S", "M", "L"};
  for (const auto& name : dsw::sizeGuideMeasurementNames())
    if (rows.front().count(name))
      g.measurements.push_back(name);
  for (std::size_t i = 0; i < rows.size(); ++i)
    g.rows.push_back({sizes[i], rows[i], {}});
  g.itemRow = item;
  return g;
}

/// Two items whose texts exercise CSV quoting: commas, quotes, a line break, non-ASCII. The
/// first is priced and graded (S, M, L; the piece is M); the second has no price and no guide.
inline std::vector<daemon::ExportItem> sampleItems() {
  daemon::ExportItem a;
  a.id = "1";
  a.sku = "SK-1001";
  a.title = "Linen skirt, \"Été\" — blue";
  a.description = "Soft linen.\nLined, with pockets; size M on the form.";
  a.type = "skirt";
  a.attributes = {{"skirt", "a_line"}};
  a.colors = {"Navy", "White"};
  a.price = 59.9;
  a.tags = {"linen", "summer, 2026"};
  a.measurementsCm = {{"waist_circ", 72.0}, {"hip_circ", 96.5}, {"skirt_length", 61.0}};
  a.sizeGuide = sampleGuide({{{"waist_circ", 67.0}, {"hip_circ", 91.5}, {"skirt_length", 60.0}},
                             {{"waist_circ", 72.0}, {"hip_circ", 96.5}, {"skirt_length", 61.0}},
                             {{"waist_circ", 77.0}, {"hip_circ", 101.5}, {"skirt_length", 62.0}}},
                            1);
  a.images = {{"images/SK-1001-product.jpg", ""}, {"images/SK-1001-cutout.png", "Cut-out"}};
  daemon::ExportItem b;
  b.id = "2";
  b.sku = "TP 2002/ü";
  b.title = "Bluse 'Grün' ★";
  b.type = "top";
  b.attributes = {{"sleeve", "short"}};
  b.printed = true;
  b.tags = {};
  b.measurementsCm = {{"bust_circ", 94.0}, {"garment_length", 58.25}};
  b.images = {{"images/TP 2002-product.jpg", ""}};
  return {a, b};
}

}  // namespace garmcap::exports_test
