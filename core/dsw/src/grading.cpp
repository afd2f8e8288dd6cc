#include "garmcap/dsw/grading.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/dsw/base_draft.h"
#include "garmcap/dsw/mean_value_coordinates.h"

namespace garmcap::dsw {
namespace {

using drafts::Panel;
using drafts::Pattern;
using Vec2 = Eigen::Vector2d;

struct Box {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void add(const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  double area() const { return hi.x() >= lo.x() && hi.y() >= lo.y() ? (hi - lo).prod() : 0.0; }
  Vec2 centre() const { return (lo + hi) / 2; }
};

Box intersect(const Box& a, const Box& b) {
  Box c;
  c.lo = a.lo.cwiseMax(b.lo);
  c.hi = a.hi.cwiseMin(b.hi);
  return c;
}

// Even-odd point in polygon; boundary points count as inside for either answer (MVC gives the
// same boundary values from both sides).
bool inside(const drafts::Polyline& poly, const Vec2& p) {
  bool in = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x)
        in = !in;
    }
  }
  return in;
}

double distanceToPolygon(const drafts::Polyline& poly, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const Vec2 e = b - a;
    const double len2 = e.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * e - p).norm());
  }
  return best;
}

const drafts::DraftRegion* findRegion(const std::vector<drafts::DraftRegion>& regions,
                                      const std::string& name) {
  for (const auto& r : regions) {
    if (r.name == name)
      return &r;
  }
  return nullptr;
}

}  // namespace

std::vector<Vec2> flattenPanel(const Panel& panel) {
  std::vector<Vec2> out(panel.outline.begin(), panel.outline.end());
  for (const auto& d : panel.darts) {
    out.push_back(d.apex);
    out.push_back(d.leg1);
    out.push_back(d.leg2);
  }
  out.push_back(panel.grainline.start);
  out.push_back(panel.grainline.end);
  for (const auto& n : panel.notches)
    out.push_back(n.position);
  for (const auto& l : panel.internalLines)
    out.insert(out.end(), l.points.begin(), l.points.end());
  return out;
}

void unflattenPanel(const std::vector<Vec2>& points, Panel& panel) {
  std::size_t k = 0;
  for (auto& p : panel.outline)
    p = points[k++];
  for (auto& d : panel.darts) {
    d.apex = points[k++];
    d.leg1 = points[k++];
    d.leg2 = points[k++];
  }
  panel.grainline.start = points[k++];
  panel.grainline.end = points[k++];
  for (auto& n : panel.notches)
    n.position = points[k++];
  for (auto& l : panel.internalLines) {
    for (auto& p : l.points)
      p = points[k++];
  }
}

Expected<EncodedPattern> encodePattern(const Pattern& source,
                                       const std::vector<drafts::DraftRegion>& sourceRegions,
                                       CoordMethod method) {
  EncodedPattern enc;
  enc.source = source;
  if (sourceRegions.empty())
    return Error{"encode: the source draft has no regions"};
  // Region names per panel: its own list, or every region when it names none.
  std::vector<std::vector<const drafts::DraftRegion*>> panelRegions;
  for (const Panel& panel : source.panels) {
    std::vector<const drafts::DraftRegion*> list;
    for (const auto& name : panel.draftRegions) {
      const drafts::DraftRegion* r = findRegion(sourceRegions, name);
      if (r == nullptr)
        return Error{"encode: panel '" + panel.name + "' names draft region '" + name +
                     "', which the draft lacks"};
      list.push_back(r);
    }
    if (list.empty()) {
      for (const auto& r : sourceRegions)
        list.push_back(&r);
    }
    panelRegions.push_back(std::move(list));
  }
  // Step 2, positioning: a group (panels naming the same regions) is kept when its bounding box
  // overlaps its regions' by at least half; else it is shifted so that the box centres meet.
  enc.panelOffset.assign(source.panels.size(), Vec2::Zero());
  std::map<std::vector<std::string>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < source.panels.size(); ++i) {
    std::vector<std::string> key;
    for (const auto* r : panelRegions[i])
      key.push_back(r->name);
    groups[key].push_back(i);
  }
  for (const auto& [names, members] : groups) {
    Box panels, regions;
    for (std::size_t i : members) {
      for (const auto& p : source.panels[i].outline)
        panels.add(p);
    }
    for (const auto* r : panelRegions[members.front()]) {
      for (const auto& p : r->polygon)
        regions.add(p);
    }
    const double overlap = intersect(panels, regions).area();
    if (panels.area() > 0 && overlap >= 0.5 * panels.area())
      continue;
    const Vec2 shift = regions.centre() - panels.centre();
    for (std::size_t i : members)
      enc.panelOffset[i] = shift;
  }
  // Step 3, encoding. Each region is converted and checked once, however many panels use it.
  std::map<const drafts::DraftRegion*, Points> cages;
  for (const auto& list : panelRegions) {
    for (const auto* r : list) {
      if (cages.count(r) == 0)
        cages.emplace(r, toPoints(r->polygon));
    }
  }
  std::map<const drafts::DraftRegion*, std::optional<std::string>> cageProblems;
  for (std::size_t pi = 0; pi < source.panels.size(); ++pi) {
    const Panel& panel = source.panels[pi];
    std::vector<Vec2> pts = flattenPanel(panel);
    enc.pointCount.push_back(pts.size());
    std::map<const drafts::DraftRegion*, std::vector<Eigen::Index>> byRegion;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      Vec2 p = pts[k] + enc.panelOffset[pi];
      if (!p.allFinite())
        return Error{"encode: panel '" + panel.name + "' point " + std::to_string(k) +
                     " is not finite"};
      // One region (the usual case: a panel and its own block) needs no choice.
      const drafts::DraftRegion* chosen =
          panelRegions[pi].size() == 1 ? panelRegions[pi].front() : nullptr;
      double best = std::numeric_limits<double>::infinity();
      for (const auto* r : chosen ? std::vector<const drafts::DraftRegion*>{} : panelRegions[pi]) {
        if (inside(r->polygon, p)) {
          chosen = r;
          break;
        }
        const double d = distanceToPolygon(r->polygon, p);
        if (d < best) {
          best = d;
          chosen = r;
        }
      }
      byRegion[chosen].push_back(static_cast<Eigen::Index>(k));
    }
    for (auto& [region, slots] : byRegion) {
      Points q(static_cast<Eigen::Index>(slots.size()), 2);
      for (std::size_t s = 0; s < slots.size(); ++s)
        q.row(static_cast<Eigen::Index>(s)) =
            (pts[static_cast<std::size_t>(slots[s])] + enc.panelOffset[pi]).transpose();
      const Points& cage = cages.at(region);
      if (method == CoordMethod::kMeanValue) {  // the other methods check their cage themselves
        auto checked = cageProblems.find(region);
        if (checked == cageProblems.end())
          checked = cageProblems.emplace(region, cageProblem(cage)).first;
        if (checked->second)
          return Error{"encode: panel '" + panel.name + "' in region '" + region->name +
                       "': mean value coordinates: " + *checked->second};
      }
      auto e = encodePointsInCheckedCage(method, cage, q);
      if (!e)
        return Error{"encode: panel '" + panel.name + "' in region '" + region->name +
                     "': " + e.error().message};
      enc.groups.push_back(
          EncodedPattern::Group{region->name, pi, std::move(slots), std::move(e).value()});
    }
  }
  return enc;
}

Expected<Pattern> decodePattern(const EncodedPattern& enc, const Pattern& targetDraft) {
  Pattern out;
  out.type = targetDraft.type;
  out.measurements = targetDraft.measurements;
  out.design = targetDraft.design;
  out.points = targetDraft.points;
  out.lines = targetDraft.lines;
  out.regions = targetDraft.regions;
  out.seams = enc.source.seams;
  out.panels = enc.source.panels;
  std::vector<std::vector<Vec2>> pts(out.panels.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    pts[i].resize(enc.pointCount[i]);
  // Regions converted once per decode.
  std::map<std::string, Points> target;
  for (const auto& g : enc.groups) {
    auto it = target.find(g.region);
    if (it == target.end()) {
      const drafts::DraftRegion* r = findRegion(targetDraft.regions, g.region);
      if (r == nullptr)
        return Error{"decode: the target draft has no region '" + g.region + "'"};
      it = target.emplace(g.region, toPoints(r->polygon)).first;
    }
    if (it->second.rows() != g.encoding.weights.cols())
      return Error{"decode: region '" + g.region + "' has " + std::to_string(it->second.rows()) +
                   " vertices in the target draft and " +
                   std::to_string(g.encoding.weights.cols()) + " in the source draft"};
    auto dec = decodePoints(g.encoding, it->second);
    if (!dec)
      return Error{"decode: region '" + g.region + "': " + dec.error().message};
    const Points& d = *dec;
    for (std::size_t s = 0; s < g.slots.size(); ++s) {
      pts[g.panel][static_cast<std::size_t>(g.slots[s])] =
          d.row(static_cast<Eigen::Index>(s)).transpose() - enc.panelOffset[g.panel];
    }
  }
  for (std::size_t i = 0; i < out.panels.size(); ++i) {
    for (const auto& p : pts[i]) {
      if (!p.allFinite())
        return Error{"decode: panel '" + out.panels[i].name + "' decoded to a non-finite point"};
    }
    unflattenPanel(pts[i], out.panels[i]);
  }
  return out;
}

// The recipe's declaration of a design parameter, if it has one.
const drafts::DesignParameter* designParameter(const std::string& type, const std::string& name) {
  for (const auto& t : drafts::garmentTypes())
    if (t.name == type)
      for (const auto& p : t.design)
        if (p.name == name)
          return &p;
  return nullptr;
}

Expected<Pattern> targetDraft(const Pattern& source, const drafts::Measurements& target) {
  std::map<std::string, double> design;
  for (const auto& [name, value] : source.design) {
    if (target.has(name))
      continue;
    design[name] = value;
    // A width the recipe grades with the body keeps its proportion to that body measurement;
    // clamped to the recipe's range so a far size stays draftable.
    const auto* p = designParameter(source.type, name);
    if (!p || p->gradesWith.empty())
      continue;
    const auto from = source.measurements.find(p->gradesWith);
    const auto to = target.find(p->gradesWith);
    if (from && to && *from > 0)
      design[name] = std::clamp(value * *to / *from, p->minValue, p->maxValue);
  }
  try {
    return drafts::draftGarment(source.type, target, design);
  } catch (const std::exception& e) {
    return Error{std::string("target draft: ") + e.what()};
  }
}

Expected<Pattern> gradePattern(const Pattern& source, const drafts::Measurements& target,
                               const GradeOptions& options) {
  bool hasRecipe = false;
  for (const auto& t : drafts::garmentTypes())
    hasRecipe = hasRecipe || t.name == source.type;
  Expected<Pattern> graded = Error{""};
  if (options.baseDraft || !hasRecipe || source.regions.empty()) {
    graded = gradeWithBaseDraft(source, target, options.method);
  } else {
    auto enc = encodePattern(source, source.regions, options.method);
    if (!enc)
      return enc.error();
    auto draft = targetDraft(source, target);
    if (!draft)
      return draft.error();
    graded = decodePattern(*enc, *draft);
  }
  if (!graded)
    return graded.error();
  if (options.dartCompensation) {
    Pattern p = std::move(graded).value();
    auto body = target.find("waist_circ");
    if (!body)
      return Error{"dart compensation: the target body has no waist_circ"};
    double margin = 0;
    if (options.marginCm) {
      margin = *options.marginCm;
    } else {
      auto own = waistMargin(source);
      if (!own)
        return Error{"dart compensation: " + own.error().message};
      margin = *own;
    }
    auto dc = compensateDarts(p, *body, margin);
    if (!dc)
      return dc.error();
    return p;
  }
  return graded;
}

Expected<double> waistMargin(const Pattern& pattern) {
  const auto body = pattern.measurements.find("waist_circ");
  if (!body)
    return Error{"the pattern's body has no waist_circ"};
  try {
    const auto m = drafts::measurePattern(pattern);
    const auto it = m.find("waist_circ");
    if (it == m.end())
      return Error{"the pattern shows no waist_circ"};
    return it->second - *body;
  } catch (const std::exception& e) {
    return Error{std::string("measuring the pattern's waist: ") + e.what()};
  }
}

Expected<DartCompensation> compensateDarts(Pattern& graded, double bodyWaistCm, double marginCm) {
  auto level = graded.points.find("level_waist");
  if (level == graded.points.end())
    return Error{"dart compensation: the pattern has no draft point 'level_waist'"};
  const double waistY = level->second.y();
  constexpr double kOnLevelCm = 0.5;
  auto atWaist = [&](const drafts::Dart& d) {
    return std::abs(d.leg1.y() - waistY) < kOnLevelCm && std::abs(d.leg2.y() - waistY) < kOnLevelCm;
  };
  auto measure = [&]() -> Expected<double> {
    try {
      const auto m = drafts::measurePattern(graded);
      auto it = m.find("waist_circ");
      if (it == m.end())
        return Error{"dart compensation: the pattern shows no waist_circ"};
      return it->second;
    } catch (const std::exception& e) {
      return Error{std::string("dart compensation: ") + e.what()};
    }
  };
  DartCompensation dc;
  dc.bodyCm = bodyWaistCm;
  // N_dart: waist darts of the panels that measurePattern sums for the waist (bodice panels).
  for (const auto& p : graded.panels) {
    if (p.name.rfind("bodice", 0) != 0)
      continue;
    const int pieces = p.cutCount * (p.cutOnFold ? 2 : 1);
    for (const auto& d : p.darts)
      dc.dartCount += atWaist(d) ? pieces : 0;
  }
  if (dc.dartCount == 0)
    return Error{"dart compensation: no dart of a bodice panel has its legs on the waist level"};
  auto before = measure();
  if (!before)
    return before.error();
  dc.garmentBeforeCm = *before;
  double garment = *before;
  for (int iter = 0; iter < 4 && std::abs(garment - bodyWaistCm - marginCm) > 0.01; ++iter) {
    const double change =
        -(marginCm + bodyWaistCm - garment) / dc.dartCount;  // eq. 4.14, sign corrected
    dc.widthChangeCm += change;
    for (auto& p : graded.panels) {
      for (auto& d : p.darts) {
        if (!atWaist(d))
          continue;
        const Vec2 along = (d.leg2 - d.leg1);
        const double width = along.norm();
        if (width + change <= 0.05)
          return Error{"dart compensation: dart '" + d.name + "' of panel '" + p.name +
                       "' would close (width " + std::to_string(width) + " cm, change " +
                       std::to_string(change) + " cm)"};
        const Vec2 move =
            along / width * (-change / 2);  // legs move toward each other when narrowing
        const Vec2 newLeg1 = d.leg1 + move, newLeg2 = d.leg2 - move;
        for (auto& v : p.outline) {
          if ((v - d.leg1).norm() < 1e-9)
            v = newLeg1;
          else if ((v - d.leg2).norm() < 1e-9)
            v = newLeg2;
        }
        d.leg1 = newLeg1;
        d.leg2 = newLeg2;
      }
    }
    auto now = measure();
    if (!now)
      return now.error();
    garment = *now;
  }
  dc.garmentAfterCm = garment;
  return dc;
}

}  // namespace garmcap::dsw
