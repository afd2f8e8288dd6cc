// Notches a pattern maker expects (issue 18): a double notch on the back armhole and on the
// back of the sleeve cap, a single one on the front; matching notches where a dress's bodice and
// skirt meet, at equal sewn distances on both pieces; and every notch in the DXF (layer 4) and
// SVG files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

namespace {

using garmcap::drafts::Panel;
using garmcap::drafts::Pattern;
using garmcap::drafts::Point2;

std::vector<Point2> notchesNamed(const Panel& p, const std::string& name) {
  std::vector<Point2> out;
  for (const auto& n : p.notches)
    if (n.name == name)
      out.push_back(n.position);
  return out;
}

const Panel* findPanel(const Pattern& p, const std::string& name) {
  for (const auto& panel : p.panels)
    if (panel.name == name)
      return &panel;
  return nullptr;
}

Pattern draft(const std::string& type, const std::string& size) {
  return garmcap::drafts::draftGarment(type, garmcap::drafts::sizeChart("korean_women").body(size),
                                       {});
}

// Distance of `q` from the segment a-b.
double segmentDistance(const Point2& q, const Point2& a, const Point2& b) {
  const Point2 ab = b - a;
  const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - q).norm();
}

// Sewn distance along the outline from vertex `from` walking `step` (+1 or -1) to the notch `q`:
// the arc length minus each dart opening passed (both legs, leg to apex to leg), since the dart
// is closed before the seam is sewn. Computed from the outline and the darts alone.
double sewnDistance(const Panel& p, int from, int step, const Point2& q) {
  const int n = static_cast<int>(p.outline.size());
  double s = 0;
  for (int k = 0, i = from; k < n; ++k, i = (i + step + n) % n) {
    const Point2 a = p.outline[static_cast<size_t>(i)];
    const Point2 b = p.outline[static_cast<size_t>((i + step + n) % n)];
    if (segmentDistance(q, a, b) < 1e-6)
      return s + (q - a).norm();
    s += (b - a).norm();
    for (const auto& d : p.darts)
      if ((b - d.apex).norm() < 1e-6)
        s -= (d.apex - a).norm() +
             (d.apex - p.outline[static_cast<size_t>((i + 2 * step + 2 * n) % n)]).norm();
  }
  ADD_FAILURE() << p.name << ": notch not on the outline";
  return -1;
}

TEST(Notches, DoubleOnTheBackArmholeSingleOnTheFront) {
  const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> types = {
      {"bodice", {"bodice_back", "bodice_front"}},
      {"dress", {"bodice_back", "bodice_front"}},
      {"blouse", {"bodice_back", "bodice_front"}},
      {"sweater", {"body_back", "body_front"}}};
  for (const auto& [type, pieces] : types) {
    for (const char* size : {"44", "66", "88"}) {
      const Pattern p = draft(type, size);
      std::vector<const Panel*> backs = {findPanel(p, pieces.first)};
      std::vector<const Panel*> fronts = {findPanel(p, pieces.second)};
      if (const Panel* sleeve = findPanel(p, "sleeve")) {
        backs.push_back(sleeve);
        fronts.push_back(sleeve);
      }
      for (const Panel* back : backs) {
        ASSERT_NE(back, nullptr) << type;
        const auto first = notchesNamed(*back, "armhole_back");
        const auto second = notchesNamed(*back, "armhole_back_2");
        ASSERT_EQ(first.size(), 1u) << type << " " << size << " " << back->name;
        ASSERT_EQ(second.size(), 1u) << type << " " << size << " " << back->name;
        // 1 cm apart along a gently curved armhole: the chord is within 0.05 cm of it.
        EXPECT_NEAR((first[0] - second[0]).norm(), 1.0, 0.05) << type << " " << back->name;
      }
      for (const Panel* front : fronts) {
        ASSERT_NE(front, nullptr) << type;
        EXPECT_EQ(notchesNamed(*front, "armhole_front").size(), 1u) << type << " " << front->name;
        EXPECT_TRUE(notchesNamed(*front, "armhole_front_2").empty()) << type << " " << front->name;
      }
    }
  }
}

TEST(Notches, DressWaistSeamNotchesSitAtEqualSewnDistances) {
  double largest = 0;
  for (const auto& size : garmcap::drafts::sizeChart("korean_women").sizes) {
    const Pattern p = draft("dress", size);
    for (const char* seamName : {"waist_back", "waist_front"}) {
      const auto seam = std::find_if(p.seams.begin(), p.seams.end(),
                                     [&](const auto& s) { return s.name == seamName; });
      ASSERT_NE(seam, p.seams.end()) << seamName;
      const Panel& a = p.panel(seam->a.panel);
      const Panel& b = p.panel(seam->b.panel);
      const auto na = notchesNamed(a, "waist_seam");
      const auto nb = notchesNamed(b, "waist_seam");
      ASSERT_EQ(na.size(), 1u) << size << " " << a.name;
      ASSERT_EQ(nb.size(), 1u) << size << " " << b.name;
      // a.from meets b.to (the file convention, both outlines counter-clockwise): walk a
      // forward from a.from and b backward from b.to.
      const double da = sewnDistance(a, seam->a.from, +1, na[0]);
      const double db = sewnDistance(b, seam->b.to, -1, nb[0]);
      EXPECT_NEAR(da, db, 0.01) << size << " " << seamName;
      largest = std::max(largest, std::abs(da - db));
      // Halfway along the sewn seam: from the other end the notch is as far (within the
      // 0.04 cm the two pieces' waist lengths may differ).
      const double da2 = sewnDistance(a, seam->a.to, -1, na[0]);
      EXPECT_NEAR(da, da2, 0.1) << size << " " << seamName;
      EXPECT_GT(da, 5.0) << size << " " << seamName;
    }
  }
  std::printf("waist-seam notches: sewn distances differ by at most %.4f mm\n", largest * 10);
}

// A dart met on a seam: where its legs close (sewn distance from the seam's start, earlier
// darts closed) and its intake (the distance between its legs).
struct DartOnSeam {
  double at = 0;
  double intake = 0;
};

// The darts opened in the outline between vertices `from` and `to`, walking by `step` (+1 or
// -1): a vertex that is a dart's apex is passed with both its legs, the rest summed as sewn.
std::vector<DartOnSeam> dartsAlong(const Panel& p, int from, int to, int step) {
  const int n = static_cast<int>(p.outline.size());
  auto at = [&](int i) { return p.outline[static_cast<size_t>(((i % n) + n) % n)]; };
  auto isApex = [&](const Point2& q) {
    return std::any_of(p.darts.begin(), p.darts.end(),
                       [&](const auto& d) { return (d.apex - q).norm() < 1e-6; });
  };
  std::vector<DartOnSeam> out;
  double s = 0;
  for (int i = from, k = 0; ((i % n) + n) % n != to && k < n; ++k) {
    if (isApex(at(i + step))) {
      out.push_back({s, (at(i + 2 * step) - at(i)).norm()});
      i += 2 * step;
      continue;
    }
    s += (at(i + step) - at(i)).norm();
    i += step;
  }
  return out;
}

// Issue 18: where a dress's bodice and skirt meet at the waist seam, each bodice dart meets a
// skirt dart of the same intake at the same place on the sewn seam (a pattern maker's rule: the
// darts run on through the seam). Measured from the outlines alone, every size of both charts.
TEST(Notches, DressWaistSeamDartsMeetDartToDart) {
  double worstAt = 0, worstIntake = 0;
  for (const std::string chart : {"korean_women", "italian_women", "french_women"}) {
    const auto& c = garmcap::drafts::sizeChart(chart);
    for (std::size_t i = 0; i < c.sizes.size(); ++i) {
      const Pattern p = garmcap::drafts::draftGarment("dress", c.bodies[i], {});
      for (const char* seamName : {"waist_back", "waist_front"}) {
        const auto seam = std::find_if(p.seams.begin(), p.seams.end(),
                                       [&](const auto& s) { return s.name == seamName; });
        ASSERT_NE(seam, p.seams.end()) << seamName;
        const Panel& a = p.panel(seam->a.panel);
        const Panel& b = p.panel(seam->b.panel);
        // a.from meets b.to: walk a forward from a.from, b backward from b.to.
        const auto da = dartsAlong(a, seam->a.from, seam->a.to, +1);
        const auto db = dartsAlong(b, seam->b.to, seam->b.from, -1);
        const std::string what = chart + " " + c.sizes[i] + " " + seamName;
        ASSERT_EQ(da.size(), 2u) << what;
        ASSERT_EQ(db.size(), da.size()) << what;
        for (std::size_t k = 0; k < da.size(); ++k) {
          EXPECT_NEAR(da[k].at, db[k].at, 0.1) << what << " dart " << k;
          EXPECT_NEAR(da[k].intake, db[k].intake, 0.1) << what << " dart " << k;
          worstAt = std::max(worstAt, std::abs(da[k].at - db[k].at));
          worstIntake = std::max(worstIntake, std::abs(da[k].intake - db[k].intake));
        }
      }
    }
  }
  std::printf("waist-seam darts: places differ by at most %.3f mm, intakes by %.3f mm\n",
              worstAt * 10, worstIntake * 10);
}

// Bodies for the dress's waist seam: every size of every chart and 200 random bodies between
// two adjacent sizes of a chart, each measurement jittered by up to +-3 %.
std::vector<garmcap::drafts::Measurements> dressBodies() {
  std::vector<garmcap::drafts::Measurements> out;
  const auto& charts = garmcap::drafts::sizeCharts();
  for (const auto& c : charts)
    out.insert(out.end(), c.bodies.begin(), c.bodies.end());
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> u(0, 1), jitter(-0.03, 0.03);
  for (std::size_t i = 0; i < 200; ++i) {
    const auto& c = charts[i % charts.size()];
    const double pos = u(rng) * static_cast<double>(c.bodies.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(pos),
                      hi = std::min(lo + 1, c.bodies.size() - 1);
    const double t = pos - static_cast<double>(lo);
    garmcap::drafts::Measurements m;
    for (const auto& [k, v] : c.bodies[lo].values())
      m.set(k, ((1 - t) * v + t * (c.bodies[hi].has(k) ? c.bodies[hi].get(k) : v)) *
                   (1 + jitter(rng)));
    out.push_back(m);
  }
  return out;
}

// The outline vertices of a panel from the one nearest `from` to the one nearest `to`, the
// shorter way round.
std::vector<Point2> outlineRun(const Panel& p, const Point2& from, const Point2& to) {
  const int n = static_cast<int>(p.outline.size());
  auto nearest = [&](const Point2& q) {
    int best = 0;
    for (int i = 1; i < n; ++i)
      if ((p.outline[static_cast<size_t>(i)] - q).norm() <
          (p.outline[static_cast<size_t>(best)] - q).norm())
        best = i;
    return best;
  };
  const int a = nearest(from), b = nearest(to);
  const int fwd = (b - a + n) % n, bwd = (a - b + n) % n;
  const int step = fwd <= bwd ? 1 : -1;
  std::vector<Point2> out;
  for (int i = a;; i = (i + step + n) % n) {
    out.push_back(p.outline[static_cast<size_t>(i)]);
    if (i == b)
      break;
  }
  return out;
}

// Issue 18: a dress's skirt takes the bodice's waist darts (dart to dart), and its side seam
// still never runs outward above the hip: from the side waist down to the hip the seam only
// moves out toward the hip (back: +x, front: -x), as a pattern maker expects; the bodice keeps
// bust, waist and hip readings of body + ease, and bodice and skirt waists sew to each other.
// Measured on the outlines, every size of every chart and 200 random bodies.
TEST(Notches, DressSkirtSideSeamNeverRunsOutAboveTheHip) {
  std::vector<double> intakes;
  double worstInward = 0, worstReading = 0, worstWaist = 0, worstAt = 0, worstIntake = 0;
  for (const auto& body : dressBodies()) {
    const Pattern p = garmcap::drafts::draftGarment("dress", body, {});
    // Side seam from the skirt's side waist to its hip notch, on each skirt piece.
    for (const auto& [piece, outward] : {std::pair{"skirt_back", 1.0}, {"skirt_front", -1.0}}) {
      const Panel& panel = p.panel(piece);
      const std::string side = outward > 0 ? "back" : "front";
      const auto run = outlineRun(panel, p.points.at("skirt_waist_side_" + side),
                                  p.points.at("skirt_hip_side_" + side));
      ASSERT_GE(run.size(), 3u) << piece;
      for (std::size_t k = 0; k + 1 < run.size(); ++k) {
        const double out = outward * (run[k + 1].x() - run[k].x());
        worstInward = std::max(worstInward, -out);
        EXPECT_GT(out, -1e-6) << piece << " vertex " << k;
        EXPECT_GT(run[k + 1].y(), run[k].y()) << piece << " vertex " << k;
      }
      intakes.push_back(outward * (run.back().x() - run.front().x()));
    }
    // Readings of body + ease.
    const auto m = garmcap::drafts::measurePattern(p);
    for (const auto& [reading, ease] : {std::pair{"bust_circ", "ease_bust"},
                                        {"waist_circ", "ease_waist"},
                                        {"hip_circ", "ease_hip"}}) {
      const double want = body.get(reading) + p.design.at(ease);
      EXPECT_NEAR(m.at(reading), want, 0.1) << reading;
      worstReading = std::max(worstReading, std::abs(m.at(reading) - want));
    }
    // Waist seams: equal sewn lengths, darts meeting dart to dart.
    for (const char* seamName : {"waist_back", "waist_front"}) {
      const auto seam = std::find_if(p.seams.begin(), p.seams.end(),
                                     [&](const auto& s) { return s.name == seamName; });
      ASSERT_NE(seam, p.seams.end()) << seamName;
      const Panel& a = p.panel(seam->a.panel);
      const Panel& b = p.panel(seam->b.panel);
      const double la = garmcap::drafts::sewnEdgeLength(a, seam->a);
      const double lb = garmcap::drafts::sewnEdgeLength(b, seam->b);
      EXPECT_NEAR(la, lb, 0.05) << seamName;
      worstWaist = std::max(worstWaist, std::abs(la - lb));
      const auto da = dartsAlong(a, seam->a.from, seam->a.to, +1);
      const auto db = dartsAlong(b, seam->b.to, seam->b.from, -1);
      ASSERT_EQ(da.size(), 2u) << seamName;
      ASSERT_EQ(db.size(), da.size()) << seamName;
      for (std::size_t k = 0; k < da.size(); ++k) {
        EXPECT_NEAR(da[k].at, db[k].at, 0.1) << seamName << " dart " << k;
        EXPECT_NEAR(da[k].intake, db[k].intake, 0.1) << seamName << " dart " << k;
        worstAt = std::max(worstAt, std::abs(da[k].at - db[k].at));
        worstIntake = std::max(worstIntake, std::abs(da[k].intake - db[k].intake));
      }
    }
  }
  std::sort(intakes.begin(), intakes.end());
  std::printf(
      "dress skirt side waist -> hip over %zu pieces: outward %.2f (min) %.2f (median) %.2f (max) "
      "cm, worst inward step %.4f cm; readings within %.4f cm; waist seams within %.4f cm; "
      "darts meet within %.4f / %.4f cm\n",
      intakes.size(), intakes.front(), intakes[intakes.size() / 2], intakes.back(), worstInward,
      worstReading, worstWaist, worstAt, worstIntake);
}

TEST(Notches, EveryNotchIsInTheDxfAndSvg) {
  for (const char* type : {"dress", "bodice", "sweater", "skirt_a", "pants", "sleeve"}) {
    const Pattern p = draft(type, "66");
    size_t notches = 0;
    for (const auto& panel : p.panels)
      notches += panel.notches.size();
    const std::string dxf = garmcap::drafts::patternDxf(p, {"NOTCH", "66"});
    const std::regex slit("LINE\\r?\\n *8\\r?\\n4\\r?\\n");
    EXPECT_EQ(static_cast<size_t>(std::distance(std::sregex_iterator(dxf.begin(), dxf.end(), slit),
                                                std::sregex_iterator())),
              notches)
        << type;
    const std::string svg = garmcap::drafts::patternSvg(p, {"NOTCH", "66"});
    const std::regex line("class=\"notch\"");
    EXPECT_EQ(static_cast<size_t>(std::distance(std::sregex_iterator(svg.begin(), svg.end(), line),
                                                std::sregex_iterator())),
              notches)
        << type;
  }
}

}  // namespace
