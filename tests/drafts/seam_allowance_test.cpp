// Cut lines with seam allowance for every garment type: the cut line encloses the net outline,
// each edge at its own allowance (1 cm seams, 3 cm hem, 0 on the fold), measured here with a
// point-to-segment distance of its own, independent of the offset code.
#include "garmcap/drafts/seam_allowance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::drafts {
namespace {

// 0.1 mm: on a concave curve tighter than a few allowances the offset edges are shortened to
// nothing and the nearest cut point is their mitre, d / cos(half the turn) away (0.06 mm at the
// back neck with a 3 cm allowance).
constexpr double kTolCm = 0.01;

double segmentDistance(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Distance from p to the closed polygon's boundary.
double ringDistance(const Point2& p, const Polyline& ring) {
  double best = 1e300;
  for (size_t i = 0; i < ring.size(); ++i)
    best = std::min(best, segmentDistance(p, ring[i], ring[(i + 1) % ring.size()]));
  return best;
}

// Distance from p to the nearest outline edge whose allowance is below `allowance` (a fold or
// a dart leg near a corner legitimately brings the cut line closer than `allowance`).
double distanceToSmallerAllowance(const Point2& p, const Panel& panel,
                                  const std::vector<double>& allowance,
                                  const std::vector<EdgeRole>& roles, double below) {
  double best = 1e300;
  const auto& o = panel.outline;
  for (size_t i = 0; i < o.size(); ++i)
    if (allowance[i] < below - 1e-9 && roles[i] != EdgeRole::Dart)
      best = std::min(best, segmentDistance(p, o[i], o[(i + 1) % o.size()]));
  return best;
}

double distanceToDart(const Point2& p, const Panel& panel, const std::vector<EdgeRole>& roles) {
  double best = 1e300;
  const auto& o = panel.outline;
  for (size_t i = 0; i < o.size(); ++i)
    if (roles[i] == EdgeRole::Dart)
      best = std::min(best, segmentDistance(p, o[i], o[(i + 1) % o.size()]));
  return best;
}

// 1 cm to the right of the edge a -> b walking up a right-hand side (y down).
Point2 outwardOf(const Point2& a, const Point2& b) {
  const Point2 e = (b - a).normalized();
  return Point2(-e.y(), e.x());
}

struct Checked {
  int edges = 0;
  int hemEdges = 0;
  int foldEdges = 0;
  int besideDart = 0;
  int exact = 0;  // edges whose midpoint lies exactly at the allowance
};

// Every edge's midpoint lies at its allowance from the cut line (farther from it only where an
// edge of smaller allowance is near), every net vertex inside the cut line.
Checked checkPanel(const Pattern& pat, const Panel& panel) {
  Checked c;
  const Polyline cut = cutOutline(panel, pat);
  EXPECT_TRUE(isSimplePolygon(cut)) << pat.type << "/" << panel.name;
  EXPECT_EQ(signedArea(cut) > 0, signedArea(panel.outline) > 0) << panel.name;
  const auto roles = edgeRoles(panel, pat);
  const auto allowance = edgeAllowances(panel, pat);
  const auto& o = panel.outline;
  for (size_t i = 0; i < o.size(); ++i) {
    const Point2 a = o[i], b = o[(i + 1) % o.size()];
    if ((b - a).norm() < 1e-6 || roles[i] == EdgeRole::Dart)
      continue;
    const double want = allowance[i];
    const Point2 mid = (a + b) / 2;
    const double got = ringDistance(mid, cut);
    const std::string where = pat.type + "/" + panel.name + " edge " + std::to_string(i) + " (" +
                              edgeRoleName(roles[i]) + ")";
    if (distanceToSmallerAllowance(mid, panel, allowance, roles, want) < want + 0.2) {
      EXPECT_LE(got, want + kTolCm) << where;  // a corner with a smaller allowance
    } else if (distanceToDart(mid, panel, roles) < want + 1.0) {
      // Beside a dart the allowance is the closed dart's (DartCapFollowsTheClosedDart); flat,
      // the cap may pass farther or nearer, never onto the seam line.
      EXPECT_GE(got, 0.5 * want - kTolCm) << where;
      ++c.besideDart;
    } else {
      EXPECT_NEAR(got, want, kTolCm) << where;
      ++c.exact;
    }
    if (roles[i] == EdgeRole::Hem) {
      EXPECT_DOUBLE_EQ(want, kHemAllowanceCm) << where;
      ++c.hemEdges;
    }
    if (roles[i] == EdgeRole::Fold) {
      EXPECT_EQ(want, 0.0) << where;
      EXPECT_LT(got, 1e-6) << where << ": the fold is the cut line";
      ++c.foldEdges;
    }
    if (roles[i] == EdgeRole::Seam || roles[i] == EdgeRole::Free) {
      EXPECT_DOUBLE_EQ(want, panel.seamAllowanceCm) << where;
    }
    ++c.edges;
  }
  for (const auto& p : o)
    EXPECT_TRUE(pointInPolygon(p, cut) || ringDistance(p, cut) < 1e-6) << panel.name;
  // No cut vertex comes nearer the net outline than the smallest allowance around it allows:
  // the cut line never cuts into the piece.
  for (const auto& v : cut)
    EXPECT_FALSE(pointInPolygon(v, o) && ringDistance(v, o) > 1e-6)
        << pat.type << "/" << panel.name << ": cut vertex inside the piece";
  for (const auto& d : panel.darts) {
    // Legs that open toward the edge: the closed dart's allowance stands over the opening.
    const Polyline legs = dartPath(panel, d);
    const double opening = (legs.front() - legs.back()).norm();
    const double below = (legs[1] - legs[legs.size() - 2]).norm();
    if (legs.size() > 3 && opening < below)
      continue;  // legs closing toward the edge (a high-waist top line): the cap dips in
    // Without allowance the cut runs along the closed seam line, which may pass either side.
    const auto at = std::find_if(o.begin(), o.end(),
                                 [&](const Point2& q) { return (q - legs.front()).norm() < 1e-9; });
    const size_t first = static_cast<size_t>(at - o.begin());
    if (at == o.end() || allowance[(first + o.size() - 1) % o.size()] == 0.0)
      continue;
    EXPECT_TRUE(pointInPolygon((d.leg1 + d.leg2) / 2, cut) ||
                ringDistance((d.leg1 + d.leg2) / 2, cut) < 1e-6)  // on it without allowance
        << panel.name << " dart " << d.name;
  }
  return c;
}

TEST(SeamAllowance, CutLineEnclosesSewLineByEachEdgesAllowanceForEveryType) {
  for (const auto& type : garmentTypes()) {
    for (const char* size : {"44", "66", "88"}) {
      const Pattern pat = draftGarment(type.name, sizeChart("korean_women").body(size));
      Checked total;
      for (const auto& panel : pat.panels) {
        SCOPED_TRACE(type.name + " " + size + " " + panel.name);
        const Checked c = checkPanel(pat, panel);
        total.edges += c.edges;
        total.hemEdges += c.hemEdges;
        total.foldEdges += c.foldEdges;
        total.exact += c.exact;
        if (foldEdge(panel, pat)) {
          EXPECT_GT(c.foldEdges, 0) << panel.name << " is cut on the fold";
        }
      }
      EXPECT_GT(total.edges, 0);
      // Most of the outline is away from corners and darts: there the allowance is exact.
      EXPECT_GT(total.exact, 0.5 * total.edges) << type.name << ": " << total.exact << " of "
                                                << total.edges << " edges at their allowance";
      EXPECT_GT(total.hemEdges, 0) << type.name << " has no hem edge";
    }
  }
}

TEST(SeamAllowance, HemIsTheBottomFreeEdgeAndTakesThreeCm) {
  const Pattern pat = draftGarment("skirt_a", sizeChart("korean_women").body("66"));
  for (const auto& panel : pat.panels) {
    const auto roles = edgeRoles(panel, pat);
    const auto cut = cutOutline(panel, pat);
    double maxNetY = -1e300, maxCutY = -1e300;
    for (const auto& p : panel.outline)
      maxNetY = std::max(maxNetY, p.y());
    for (const auto& p : cut)
      maxCutY = std::max(maxCutY, p.y());
    // The lowest point of an A-line skirt panel is on its hem, 3 cm above the cut line's.
    EXPECT_NEAR(maxCutY - maxNetY, kHemAllowanceCm, 0.3) << panel.name;
    for (size_t i = 0; i < roles.size(); ++i)
      if (roles[i] == EdgeRole::Hem) {
        EXPECT_GT(panel.outline[i].y(), maxNetY - 10) << panel.name << ": hem edge up the piece";
      }
  }
}

TEST(SeamAllowance, PanelSeamAllowanceIsUsedOnSeams) {
  Pattern pat = draftGarment("skirt_h", sizeChart("korean_women").body("66"));
  for (auto& panel : pat.panels)
    panel.seamAllowanceCm = 1.5;
  for (const auto& panel : pat.panels) {
    const auto roles = edgeRoles(panel, pat);
    const auto allowance = edgeAllowances(panel, pat);
    for (size_t i = 0; i < roles.size(); ++i)
      if (roles[i] == EdgeRole::Seam) {
        EXPECT_DOUBLE_EQ(allowance[i], 1.5);
      }
    checkPanel(pat, panel);
  }
}

TEST(SeamAllowance, EveryTypeAtTheDesignParametersRange) {
  // seam_allowance runs from 0 to 3 cm (recipe_registry.cpp): every cut line is still built.
  for (const auto& type : garmentTypes()) {
    for (double sa : {0.0, 2.0, 3.0}) {
      const Pattern pat =
          draftGarment(type.name, sizeChart("korean_women").body("55"), {{"seam_allowance", sa}});
      for (const auto& panel : pat.panels) {
        SCOPED_TRACE(type.name + " seam_allowance " + std::to_string(sa) + " " + panel.name);
        ASSERT_DOUBLE_EQ(panel.seamAllowanceCm, sa);
        checkPanel(pat, panel);
      }
    }
  }
}

TEST(SeamAllowance, EveryTypeAtEverySizeOfEveryChart) {
  int pieces = 0;
  for (const auto& type : garmentTypes())
    for (const auto& chart : sizeCharts())
      for (size_t i = 0; i < chart.bodies.size(); ++i) {
        Pattern pat;
        try {
          pat = draftGarment(type.name, chart.bodies[i]);
        } catch (const std::exception&) {
          continue;  // a body a recipe refuses (recipe_acceptance_test says which may)
        }
        for (const auto& panel : pat.panels) {
          SCOPED_TRACE(type.name + " " + chart.name + " " + chart.sizes[i] + " " + panel.name);
          checkPanel(pat, panel);
          ++pieces;
        }
      }
  EXPECT_GT(pieces, 100);
}

TEST(SeamAllowance, CapAndShortSleevesGetTheirCutLinesAndAHem) {
  const Measurements body = sizeChart("korean_women").body("55");
  for (const char* type : {"dress", "blouse", "sweater", "sleeve"})
    for (const double cm : {8.0, 15.0, 22.0}) {
      const Pattern pat =
          draftGarment(type, body, {{"sleeve_length", cm / body.get("arm_shoulder_tip_to_wrist")}});
      for (const auto& panel : pat.panels) {
        SCOPED_TRACE(std::string(type) + " sleeve " + std::to_string(cm) + " " + panel.name);
        checkPanel(pat, panel);
        if (panel.name == "sleeve") {
          const auto roles = edgeRoles(panel, pat);
          EXPECT_NE(std::find(roles.begin(), roles.end(), EdgeRole::Hem), roles.end());
        }
      }
    }
}

TEST(SeamAllowance, SquareWithFoldHemAndSeam) {
  // A hand-built 20 x 30 cm piece cut on the fold at x = 0 (left), hem at the bottom: the cut
  // line is the rectangle from (0, -1) to (21, 33), computed by hand.
  Pattern pat;
  pat.type = "test";
  Panel p;
  p.name = "piece";
  p.cutOnFold = true;
  p.outline = {{0, 0}, {0, 30}, {20, 30}, {20, 0}};
  pat.panels.push_back(p);
  pat.seams.push_back({"side", {"piece", 2, 3}, {"piece", 2, 3}, 0});
  const auto roles = edgeRoles(p, pat);
  ASSERT_EQ(roles.size(), 4u);
  EXPECT_EQ(roles[0], EdgeRole::Fold);
  EXPECT_EQ(roles[1], EdgeRole::Hem);
  EXPECT_EQ(roles[2], EdgeRole::Seam);
  EXPECT_EQ(roles[3], EdgeRole::Free);
  const Polyline cut = cutOutline(p, pat);
  const Polyline want = {{0, -1}, {0, 33}, {21, 33}, {21, -1}};
  ASSERT_EQ(cut.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i)
    EXPECT_LT((cut[i] - want[i]).norm(), 1e-9) << i << ": " << cut[i].transpose();
}

TEST(SeamAllowance, FlaredHemCornerIsTruedAsTheSideSeamsMirror) {
  // A flared piece: fold at x = 0, hem y = 30 from x = 0 to 25, side seam up to (20, 0). The
  // side's cut line (1 cm out) meets the hem line at x = 25 + 1 / cos(atan(5/30)) and then runs
  // on as its mirror image about the hem line, reaching the hem's cut line (y = 33) 0.5 cm
  // further in, not 0.5 cm further out as the plain mitre would.
  Pattern pat;
  pat.type = "test";
  Panel p;
  p.name = "piece";
  p.cutOnFold = true;
  p.outline = {{0, 0}, {0, 30}, {25, 30}, {20, 0}};
  pat.panels.push_back(p);
  pat.seams.push_back({"side", {"piece", 2, 3}, {"piece", 2, 3}, 0});
  ASSERT_EQ(edgeRoles(p, pat)[1], EdgeRole::Hem);
  const double onHemLineX = 25 + 1 / std::cos(std::atan(5.0 / 30.0));
  const Point2 onHemLine(onHemLineX, 30), turned(onHemLineX - 3.0 * 5.0 / 30.0, 33);
  const Polyline cut = cutOutline(p, pat);
  for (const Point2& want : {onHemLine, turned})
    EXPECT_TRUE(std::any_of(cut.begin(), cut.end(), [&](const Point2& q) {
      return (q - want).norm() < 1e-9;
    })) << want.transpose();
  // Folded up along the hem line, the hem allowance's side lies on the side seam's cut line.
  const Line sideCut{Point2(25, 30) + outwardOf({25, 30}, {20, 0}), Point2(-5, -30)};
  EXPECT_NEAR(signedDistanceToLine(mirrorPoint(turned, Line::horizontal(30)), sideCut), 0, 1e-9);
}

TEST(SeamAllowance, DartCapFollowsTheClosedDart) {
  // A 20 cm wide piece whose top edge has a 4 cm dart, 10 cm deep, at x = 10 (y down: the
  // dart opens at y = 0 and points down to y = 10). Legs first at x = 8.
  Pattern pat;
  pat.type = "test";
  Panel p;
  p.name = "piece";
  p.outline = {{0, 0}, {0, 30}, {20, 30}, {20, 0}, {12, 0}, {10, 10}, {8, 0}};
  p.darts.push_back({"d", {10, 10}, {12, 0}, {8, 0}});
  pat.panels.push_back(p);
  const auto roles = edgeRoles(p, pat);
  EXPECT_EQ(roles[4], EdgeRole::Dart);
  EXPECT_EQ(roles[5], EdgeRole::Dart);
  const Polyline cut = cutOutline(p, pat);
  // Pressed toward the first leg (12,0)-(10,10): the cap peak lies on the dart's centre line
  // x = 10 above the opening, where the top edge's cut line (y = -1, x > 12) mirrored about
  // the leg meets it. Mirror of y = -1 about the leg line through (12,0) and (10,10):
  const Line leg = *Line::through({12, 0}, {10, 10});
  const Point2 m0 = mirrorPoint({20, -1}, leg), m1 = mirrorPoint({14, -1}, leg);
  const Point2 peak = *intersectLines(Line{m0, m1 - m0}, Line::vertical(10));
  const auto it = std::find_if(cut.begin(), cut.end(),
                               [&](const Point2& q) { return (q - peak).norm() < 1e-9; });
  EXPECT_NE(it, cut.end()) << "no cap peak at " << peak.transpose();
  EXPECT_LT(peak.y(), -1.0);
  // Both cap feet lie on the legs extended, on the line y = -1.
  for (const Point2& foot : {Point2(12 + 0.2, -1), Point2(8 - 0.2, -1)})
    EXPECT_TRUE(std::any_of(cut.begin(), cut.end(), [&](const Point2& q) {
      return (q - foot).norm() < 1e-9;
    })) << foot.transpose();
  EXPECT_TRUE(isSimplePolygon(cut));
}

TEST(SeamAllowance, VerticalDartPressedTowardTheFold) {
  // An asymmetric top edge: flat right of the dart, sloping left of it, the fold at x = 0. The
  // intake goes toward the fold, i.e. the second leg (8,0) along the outline; that cap is the
  // mirror image (about x = 10) of the cap of the mirrored piece pressed toward its first leg
  // (no centre line there), as the mirrored piece's first leg is the mirror of this second one.
  auto piece = [](const Polyline& outline, bool onFold) {
    Pattern pat;
    pat.type = "test";
    Panel p;
    p.name = "piece";
    p.cutOnFold = onFold;
    p.outline = outline;
    p.darts.push_back({"d", {10, 10}, outline[4], outline[6]});
    pat.panels.push_back(p);
    return pat;
  };
  const Polyline net = {{0, -1}, {0, 30}, {20, 30}, {20, 0}, {12, 0}, {10, 10}, {8, 0}};
  const Pattern folded = piece(net, true);
  ASSERT_TRUE(foldEdge(folded.panels[0], folded));
  // Mirrored about x = 10 and walked backward (same orientation), starting at the same corner.
  Polyline mirrored;
  for (size_t k = 0; k < net.size(); ++k) {
    const Point2& q = net[(net.size() - k + 3) % net.size()];  // (20,0), (20,30), ...
    mirrored.emplace_back(20 - q.x(), q.y());
  }
  // mirrored: (0,0) (0,30) (20,30) (20,-1) (12,0) (10,10) (8,0): legs (12,0) then (8,0).
  ASSERT_LT((mirrored[4] - Point2(12, 0)).norm(), 1e-12);
  const Pattern plain = piece(mirrored, false);
  auto capNearDart = [](const Polyline& cut) {
    Polyline out;
    for (const auto& q : cut)
      if (std::abs(q.x() - 10) < 4 && q.y() < 0)
        out.push_back(q);
    return out;
  };
  Polyline got = capNearDart(cutOutline(folded.panels[0], folded));
  Polyline want = capNearDart(cutOutline(plain.panels[0], plain));
  for (auto& q : want)
    q.x() = 20 - q.x();
  ASSERT_EQ(got.size(), want.size());
  ASSERT_GE(got.size(), 3u);
  std::sort(got.begin(), got.end(), [](auto& a, auto& b) { return a.x() < b.x(); });
  std::sort(want.begin(), want.end(), [](auto& a, auto& b) { return a.x() < b.x(); });
  for (size_t k = 0; k < got.size(); ++k)
    EXPECT_LT((got[k] - want[k]).norm(), 1e-9)
        << got[k].transpose() << " vs " << want[k].transpose();
  // And it differs from pressing toward the first leg (the same piece without a fold).
  const Pattern unfolded = piece(net, false);
  Polyline other = capNearDart(cutOutline(unfolded.panels[0], unfolded));
  std::sort(other.begin(), other.end(), [](auto& a, auto& b) { return a.x() < b.x(); });
  double largest = 0;
  for (size_t k = 0; k < std::min(other.size(), got.size()); ++k)
    largest = std::max(largest, (other[k] - got[k]).norm());
  EXPECT_GT(largest, 0.01) << "the press direction changes the cap";
}

}  // namespace
}  // namespace garmcap::drafts
