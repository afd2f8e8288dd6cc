// Measuring panels as the seed's table 4.3 does: girths are sums of panel widths at a level
// (darts closed) times the pieces cut, lengths are taken between landmarks of the panels.
// Levels and landmarks come from the pattern's named draft points; a landmark is matched to
// the nearest outline vertex of the panel, so graded panels (whose vertices moved with the
// draft) are measured at their own corners.
#include "garmcap/drafts/panel_measure.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <stdexcept>

#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/seam_allowance.h"

namespace garmcap::drafts {
namespace {

constexpr double kLevelOffsetCm = 1e-3;  // chords are taken just inside a panel edge

bool same(const Point2& a, const Point2& b) {
  return (a - b).norm() < 1e-6;
}

double pieces(const Panel& p) {
  return p.cutCount * (p.cutOnFold ? 2.0 : 1.0);
}

bool isBodyPanel(const Panel& p) {
  return p.name.rfind("sleeve", 0) != 0;
}

// Width of the fish-eye darts drawn inside the panel (internal lines named "dart:*") on the
// horizontal line y.
double internalDartWidth(const Panel& p, double y) {
  double w = 0;
  for (const auto& l : p.internalLines) {
    if (l.name.rfind("dart:", 0) != 0)
      continue;
    auto hits = intersectPolylineLine(l.points, Line::horizontal(y));
    std::vector<double> xs;
    for (const auto& h : hits)
      xs.push_back(h.point.x());
    std::sort(xs.begin(), xs.end());
    for (std::size_t i = 0; i + 1 < xs.size(); i += 2)
      w += xs[i + 1] - xs[i];
  }
  return w;
}

class Measurer {
 public:
  explicit Measurer(const Pattern& p) : p_(p) {}

  const Point2& point(const std::string& name) const {
    auto it = p_.points.find(name);
    if (it == p_.points.end()) {
      throw DraftError("measure: pattern of type '" + p_.type + "' has no draft point '" + name +
                       "'");
    }
    return it->second;
  }
  bool hasPoint(const std::string& name) const { return p_.points.count(name) != 0; }
  const Panel* panel(const std::string& name) const {
    for (const auto& x : p_.panels) {
      if (x.name == name)
        return &x;
    }
    return nullptr;
  }
  const Panel& needPanel(const std::string& name) const {
    const Panel* x = panel(name);
    if (!x)
      throw DraftError("measure: pattern of type '" + p_.type + "' has no panel '" + name + "'");
    return *x;
  }
  int vertex(const Panel& panel, const std::string& pointName) const {
    auto i = nearestOutlineVertex(panel, point(pointName), 1.0);
    if (!i) {
      throw DraftError("measure: panel '" + panel.name + "' has no corner near draft point '" +
                       pointName + "'");
    }
    return *i;
  }
  // Sum over body panels of width x pieces at the level (just below it when `below`).
  double girth(const std::string& level, bool below, const std::string& prefix = "") const {
    const double y = point(level).y() + (below ? kLevelOffsetCm : -kLevelOffsetCm);
    double g = 0;
    for (const auto& panel : p_.panels) {
      if (!isBodyPanel(panel) || panel.name.rfind(prefix, 0) != 0)
        continue;
      g += (panelWidthAtLevel(panel, y) - internalDartWidth(panel, y)) * pieces(panel);
    }
    return g;
  }
  // Sewn length along a panel edge between two landmarks (the shorter way round).
  double along(const std::string& panelName, const std::string& from, const std::string& to) const {
    const Panel& panel = needPanel(panelName);
    const int a = vertex(panel, from), b = vertex(panel, to);
    return std::min(sewnEdgeLength(panel, EdgeRef{panel.name, a, b}),
                    sewnEdgeLength(panel, EdgeRef{panel.name, b, a}));
  }
  double pieceCount(const std::string& panelName) const { return pieces(needPanel(panelName)); }
  // Hem of the named panels, each along its own hem edge times its pieces (or once, `timesPieces`
  // false: a trouser leg opening is one front and one back).
  double hem(std::initializer_list<const char*> panels, bool timesPieces) const {
    double h = 0;
    for (const char* name : panels) {
      const Panel& panel = needPanel(name);
      const double len = hemEdgeLength(panel, p_);
      if (len <= 0)
        throw DraftError("measure: panel '" + panel.name + "' of type '" + p_.type +
                         "' has no hem edge");
      h += len * (timesPieces ? pieces(panel) : 1.0);
    }
    return h;
  }
  // The panel's hem edge as the outline vertices it runs between, in outline order: `first`
  // starts the first hem edge, `last` ends the last one. A panel whose hem edges are not one run
  // (or that has none) is refused: its hem ends cannot be told.
  struct HemEnds {
    int first = 0, last = 0;
  };
  HemEnds hemEnds(const Panel& panel) const {
    const std::vector<EdgeRole> roles = edgeRoles(panel, p_);
    const int n = static_cast<int>(roles.size());
    auto isHem = [&](int i) {
      return roles[static_cast<std::size_t>((i % n + n) % n)] == EdgeRole::Hem;
    };
    std::optional<HemEnds> ends;
    for (int i = 0; i < n; ++i) {
      if (!isHem(i) || isHem(i - 1))
        continue;
      if (ends)
        throw DraftError("measure: panel '" + panel.name + "' of type '" + p_.type +
                         "' has a hem in more than one piece");
      int last = i;
      while (isHem(last + 1) && (last + 1) % n != i)
        ++last;
      ends = HemEnds{i, (last + 1) % n};
    }
    if (!ends)
      throw DraftError("measure: panel '" + panel.name + "' of type '" + p_.type +
                       "' has no hem edge");
    return *ends;
  }
  // The edge of `panelName` in the seam `seamName`, and the vertex where it meets the panel's
  // hem: the real end of a side seam at the hem, wherever a design moved it.
  struct SeamToHem {
    EdgeRef edge;
    int hemVertex = 0;
  };
  SeamToHem seamToHem(const std::string& seamName, const std::string& panelName) const {
    const Panel& panel = needPanel(panelName);
    const HemEnds hem = hemEnds(panel);
    for (const auto& s : p_.seams) {
      if (s.name != seamName)
        continue;
      for (const EdgeRef* e : {&s.a, &s.b}) {
        if (e->panel != panelName)
          continue;
        for (const int v : {e->from, e->to})
          if (v == hem.first || v == hem.last)
            return {*e, v};
      }
    }
    throw DraftError("measure: panel '" + panelName + "' of type '" + p_.type + "' has no seam '" +
                     seamName + "' ending at its hem");
  }
  // Sewn length of the edge of `panelName` in the seam `seamName` (its first, for a twin seam).
  double seamEdgeLength(const std::string& seamName, const std::string& panelName) const {
    for (const auto& s : p_.seams) {
      if (s.name != seamName)
        continue;
      for (const EdgeRef* e : {&s.a, &s.b})
        if (e->panel == panelName)
          return sewnEdgeLength(needPanel(panelName), *e);
    }
    throw DraftError("measure: panel '" + panelName + "' of type '" + p_.type + "' has no seam '" +
                     seamName + "'");
  }
  // Where the hem edge of `panel` crosses the vertical x (a sleeve's centre line): the lowest
  // crossing, or nullopt when the hem does not span x.
  std::optional<double> hemYAt(const Panel& panel, double x) const {
    const HemEnds hem = hemEnds(panel);
    const int n = static_cast<int>(panel.outline.size());
    Polyline run;
    for (int i = hem.first;; i = (i + 1) % n) {
      run.push_back(panel.outline[static_cast<std::size_t>(i)]);
      if (i == hem.last)
        break;
    }
    std::optional<double> y;
    for (const auto& h : intersectPolylineLine(run, Line::vertical(x)))
      y = y ? std::max(*y, h.point.y()) : h.point.y();
    return y;
  }
  double design(const std::string& name, double dflt) const {
    auto it = p_.design.find(name);
    return it == p_.design.end() ? dflt : it->second;
  }

 private:
  const Pattern& p_;
};

}  // namespace

double sewnEdgeLength(const Panel& panel, const EdgeRef& edge) {
  const int n = static_cast<int>(panel.outline.size());
  if (edge.from < 0 || edge.from >= n || edge.to < 0 || edge.to >= n) {
    throw std::out_of_range("panel '" + panel.name + "': edge " + std::to_string(edge.from) + ".." +
                            std::to_string(edge.to) + " outside 0.." + std::to_string(n - 1));
  }
  // Indices along the edge.
  std::vector<int> idx;
  for (int i = edge.from;; i = (i + 1) % n) {
    idx.push_back(i);
    if (i == edge.to)
      break;
  }
  auto at = [&](std::size_t k) { return panel.outline[static_cast<std::size_t>(idx[k])]; };
  double len = 0;
  std::size_t k = 0;
  while (k + 1 < idx.size()) {
    // A dart opening here: jump to its other leg when that leg is further along this edge.
    std::size_t jump = 0;
    for (const auto& d : panel.darts) {
      const Point2* other = nullptr;
      if (same(at(k), d.leg1))
        other = &d.leg2;
      if (same(at(k), d.leg2))
        other = &d.leg1;
      if (!other)
        continue;
      for (std::size_t m = k + 1; m < idx.size(); ++m) {
        if (same(at(m), *other)) {
          jump = m;
          break;
        }
      }
      if (jump)
        break;
    }
    if (jump) {
      k = jump;
      continue;
    }
    len += (at(k + 1) - at(k)).norm();
    ++k;
  }
  return len;
}

double hemEdgeLength(const Panel& panel, const Pattern& pattern) {
  const std::vector<EdgeRole> roles = edgeRoles(panel, pattern);
  const std::size_t n = panel.outline.size();
  double len = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (roles[i] == EdgeRole::Hem)
      len += (panel.outline[(i + 1) % n] - panel.outline[i]).norm();
  return len;
}

double panelWidthAtLevel(const Panel& panel, double levelCm) {
  if (panel.outline.size() < 3)
    return 0;
  const Polyline closed = joined(panel.outline, Polyline{panel.outline.front()});
  auto hits = intersectPolylineLine(closed, Line::horizontal(levelCm));
  std::vector<double> xs;
  for (const auto& h : hits)
    xs.push_back(h.point.x());
  std::sort(xs.begin(), xs.end());
  xs.erase(
      std::unique(xs.begin(), xs.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
      xs.end());
  double w = 0;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2)
    w += xs[i + 1] - xs[i];
  return w;
}

std::optional<int> nearestOutlineVertex(const Panel& panel, const Point2& p, double toleranceCm) {
  std::optional<int> best;
  double bestD = toleranceCm;
  for (std::size_t i = 0; i < panel.outline.size(); ++i) {
    const double d = (panel.outline[i] - p).norm();
    if (d <= bestD) {
      bestD = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

std::map<std::string, double> measurePattern(const Pattern& pattern) {
  Measurer m(pattern);
  std::map<std::string, double> out;
  const std::string& t = pattern.type;
  const bool top =
      t == "bodice" || t == "dress" || t == "blouse" || t == "sweater" || t == "dress_shift";
  // Pieces cut from the shoulder to the hem in one (no waist seam).
  const bool onePiece = t == "sweater" || t == "dress_shift";
  const bool skirtTop = t == "skirt_h" || t == "skirt_a" || t == "dress";
  // Bust and waist.
  if (top) {
    out["bust_circ"] = m.girth("level_bust", true);
    if (t == "blouse" || t == "dress_shift")
      out["waist_circ"] = m.girth("level_waist", true);
    else if (t != "sweater")
      out["waist_circ"] = m.girth("level_waist", false, "bodice");
    const std::string back = onePiece ? "body_back" : "bodice_back";
    const Panel& pb = m.needPanel(back);
    out["neck_back_to_waist_b"] =
        std::abs(m.point("level_waist").y() -
                 pb.outline[static_cast<std::size_t>(m.vertex(pb, "neck_back_cb"))].y());
    const std::string front = onePiece ? "body_front" : "bodice_front";
    const double fah = m.along(front, "shoulder_tip_front", "bust_side");
    const double bah = m.along(back, "shoulder_tip_back", "bust_side");
    out["armhole_front"] = fah;
    out["armhole_back"] = bah;
    out["armscye_circ"] = fah + bah;
  }
  if (skirtTop && t != "dress") {
    out["waist_circ"] = m.along("skirt_back", "skirt_waist_cb", "skirt_waist_side_back") *
                            m.pieceCount("skirt_back") +
                        m.along("skirt_front", "skirt_waist_side_front", "skirt_waist_cf") *
                            m.pieceCount("skirt_front");
  }
  if (t == "skirt_high_waist") {
    out["waist_circ"] = m.girth("level_waist", true);
    out["top_circ"] =
        m.along("skirt_back", "skirt_top_cb", "skirt_top_side_back") * m.pieceCount("skirt_back") +
        m.along("skirt_front", "skirt_top_side_front", "skirt_top_cf") *
            m.pieceCount("skirt_front");
  }
  if (t == "pants") {
    out["waist_circ"] =
        m.along("pants_back", "waist_side_back", "waist_cb") * m.pieceCount("pants_back") +
        m.along("pants_front", "waist_side_front", "waist_cf") * m.pieceCount("pants_front");
  }
  // Hip: wherever a hip level exists and the panels reach below it.
  if (m.hasPoint("level_hip")) {
    const double yHip = m.point("level_hip").y();
    bool reaches = false;  // some body panel goes below the hip (a dress's bodices do not)
    for (const auto& p : pattern.panels) {
      if (!isBodyPanel(p))
        continue;
      double maxY = -1e9;
      for (const auto& v : p.outline)
        maxY = std::max(maxY, v.y());
      if (maxY > yHip + 0.5)
        reaches = true;
    }
    if (reaches)
      out["hip_circ"] = m.girth("level_hip", true);
  }
  // Skirt length and hem. Hems are measured along each panel's own hem edge (the free edge at
  // its bottom, seam_allowance.h), not between the draft's hem corners: a design that flares or
  // reshapes the hem moves the panel's vertices away from the draft points (issue 18: a dress
  // flared to 126 cm read 94.5 at the un-flared corners).
  if (t == "skirt_h" || t == "skirt_a" || t == "skirt_high_waist" || t == "dress") {
    const Panel& f = m.needPanel("skirt_front");
    out["skirt_length"] =
        std::abs(f.outline[static_cast<std::size_t>(m.vertex(f, "skirt_hem_cf"))].y() -
                 (t == "skirt_high_waist"
                      ? m.point("level_waist").y()
                      : f.outline[static_cast<std::size_t>(m.vertex(f, "skirt_waist_cf"))].y()));
    out["hem_circ"] = m.hem({"skirt_back", "skirt_front"}, true);
  }
  // A blouse ends below the waist: its hem, measured like a skirt's (the simulator dresses the
  // form in a blouse when it draws a top from a size chart).
  if (t == "blouse") {
    out["hem_circ"] = m.hem({"bodice_back", "bodice_front"}, true);
  }
  // Trouser lengths end where the in- and outseam edges meet the front's hem edge (not at the
  // draft's hem corners, which a design that lengthens, tapers or flares the leg leaves behind).
  if (t == "pants") {
    const Panel& f = m.needPanel("pants_front");
    const auto outseam = m.seamToHem("outseam", "pants_front");
    const auto inseam = m.seamToHem("inseam", "pants_front");
    out["pants_length"] = std::abs(f.outline[static_cast<std::size_t>(outseam.hemVertex)].y() -
                                   m.point("level_waist").y());
    out["inseam_length"] = sewnEdgeLength(f, inseam.edge);
    out["outseam_length"] = sewnEdgeLength(f, outseam.edge);
    // The crotch is read along the panels' own crotch seam edges (the front and back rise,
    // each sewn to its twin), so a crotch deepened or lengthened after drafting is read as made.
    out["crotch_length"] = m.seamEdgeLength("centre_front", "pants_front") +
                           m.seamEdgeLength("centre_back", "pants_back");
    out["hem_circ"] = m.hem({"pants_front", "pants_back"}, false);
  }
  // The hem of the body of a sweater (no darts, cut on the fold at CB and CF).
  if (t == "sweater")
    out["hem_circ"] = m.hem({"body_back", "body_front"}, true);
  // A shift dress: its skirt length from the waist level to the hem at CF, as a dress's.
  if (t == "dress_shift") {
    const Panel& f = m.needPanel("body_front");
    out["skirt_length"] = std::abs(f.outline[static_cast<std::size_t>(m.vertex(f, "hem_cf"))].y() -
                                   m.point("level_waist").y());
    out["hem_circ"] = m.hem({"body_back", "body_front"}, true);
  }
  // Sleeve.
  if (const Panel* s = m.panel("sleeve")) {
    const Point2 topV = s->outline[static_cast<std::size_t>(m.vertex(*s, "sleeve_cap_top"))];
    // A cap sleeve (no underarm seam) ends on the cap: its cap is the part from hem to hem
    // over the top, and its ease is what that part eases into the armhole it is sewn to.
    const bool capOnly =
        std::none_of(pattern.seams.begin(), pattern.seams.end(),
                     [](const SeamPair& x) { return x.name == "sleeve_underarm"; });
    if (capOnly) {
      // Read at its own hem edge like a sleeve with an underarm seam: the free edge at its
      // bottom (in a garment the cap's edges are sewn to the armhole; drafted alone, the cap
      // meets its straight hem at corners), so a cap lengthened, flared or tapered after
      // drafting is read as made. Its length runs down the centre line from the cap top to the
      // hem, and its cap is the rest of its outline, from hem end to hem end over the top.
      const auto hem = m.hemEnds(*s);
      const auto hemY = m.hemYAt(*s, topV.x());
      if (!hemY)
        throw DraftError("measure: the cap sleeve's hem of type '" + t +
                         "' does not cross its centre line");
      out["sleeve_length"] = *hemY - topV.y();
      out["sleeve_hem_circ"] = m.hem({"sleeve"}, false);
      out["sleeve_cap_length"] = sewnEdgeLength(*s, EdgeRef{s->name, hem.last, hem.first});
      double armholeSewn = 0;
      bool sewn = false;
      for (const auto& x : pattern.seams) {
        if (x.name.rfind("armhole", 0) == 0 && x.b.panel == "sleeve") {
          armholeSewn += sewnEdgeLength(pattern.panel(x.a.panel), x.a);
          sewn = true;
        }
      }
      if (sewn)
        out["sleeve_cap_ease"] = out["sleeve_cap_length"] - armholeSewn;
      return out;
    }
    out["sleeve_cap_length"] = m.along("sleeve", "sleeve_underarm_front", "sleeve_cap_top") +
                               m.along("sleeve", "sleeve_cap_top", "sleeve_underarm_back");
    out["sleeve_biceps_circ"] =
        panelWidthAtLevel(*s, m.point("sleeve_underarm_front").y() + kLevelOffsetCm);
    // A sleeve with an underarm seam is read at its own hem edge (the free edge between the
    // ends of the underarm seam): its length down the centre line from the cap top, its opening
    // along the hem, so a design that tapers, flares or lengthens the hem is read as made.
    const auto hemY = m.hemYAt(*s, topV.x());
    if (!hemY)
      throw DraftError("measure: the sleeve's hem of type '" + t +
                       "' does not cross its centre line");
    out["sleeve_length"] = *hemY - topV.y();
    out["sleeve_hem_circ"] = m.hem({"sleeve"}, false);
    if (out.count("armscye_circ"))
      out["sleeve_cap_ease"] = out["sleeve_cap_length"] - out["armscye_circ"];
    if (auto arm = pattern.measurements.find("arm_shoulder_tip_to_wrist")) {
      const double wristY = topV.y() + *arm;
      if (wristY <= *hemY + 1e-6)
        out["arm_wrist_circ"] = panelWidthAtLevel(*s, wristY - kLevelOffsetCm);
    }
  }
  return out;
}

}  // namespace garmcap::drafts
