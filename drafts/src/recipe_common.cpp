#include "recipe_common.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "garmcap/drafts/panel_edges.h"
#include "geometry_polyline_cum.h"

namespace garmcap::drafts::detail {

Polyline curve(const std::vector<CurveNode>& nodes, int count) {
  return sampleByArcLength(smoothCurve(nodes), count);
}

const Point2& DraftBuilder::point(const std::string& name, const Point2& p) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) {
    refuse("point '" + name + "' could not be constructed (the measurements do not fit together)");
  }
  return p_.points[name] = p;
}

const Point2& DraftBuilder::at(const std::string& name) const {
  auto it = p_.points.find(name);
  if (it == p_.points.end())
    throw std::logic_error(recipe_ + ": no draft point '" + name + "'");
  return it->second;
}

void DraftBuilder::contour(const std::string& name, const Polyline& pl) {
  p_.lines.push_back(DraftLine{name, pl, false});
}

void DraftBuilder::construction(const std::string& name, const Polyline& pl) {
  p_.lines.push_back(DraftLine{name, pl, true});
}

void DraftBuilder::refuse(const std::string& message) const {
  throw DraftError("recipe '" + recipe_ + "': " + message);
}

double DraftBuilder::design(const std::string& name) const {
  auto it = p_.design.find(name);
  if (it == p_.design.end()) {
    throw std::logic_error("recipe '" + recipe_ + "' uses undeclared design parameter '" + name +
                           "'");
  }
  return it->second;
}

double DraftBuilder::measurement(const std::string& name) const {
  auto v = p_.measurements.find(name);
  if (!v)
    refuse("missing measurement '" + name + "'");
  return *v;
}

std::optional<LineWithDarts> openDarts(const Polyline& line, std::vector<DartSpec> darts,
                                       int pieceCount) {
  std::sort(darts.begin(), darts.end(),
            [](const DartSpec& a, const DartSpec& b) { return a.centreS < b.centreS; });
  const std::vector<double> cum = cumulativeLengths(line);  // the line is long: sum it once
  const double total = cum.empty() ? 0.0 : cum.back();
  LineWithDarts out;
  double s = 0;
  for (const auto& d : darts) {
    const double s1 = d.centreS - d.width / 2;
    const double s2 = d.centreS + d.width / 2;
    if (d.width <= 0.05 || s1 < s + 0.3 || s2 > total - 0.3)
      return std::nullopt;
    const Polyline piece = resample(subPolyline(line, cum, s, s1), pieceCount);
    append(out.points, piece);
    out.sewnLength += polylineLength(piece);
    const Point2 leg1 = pointAtLength(line, cum, s1);
    const Point2 leg2 = pointAtLength(line, cum, s2);
    // Apex on the perpendicular bisector of the legs at the requested height: legs equal.
    const Point2 mid = midpoint(leg1, leg2);
    Point2 n = perpendicularVector(leg2 - leg1).normalized();
    if (std::abs(n.y()) < 0.2)
      return std::nullopt;
    const double t = (d.apexY - mid.y()) / n.y();
    const Point2 apex = mid + t * n;
    append(out.points, apex);
    out.darts.push_back(Dart{d.name, apex, leg1, leg2});
    s = s2;
  }
  const Polyline last = resample(subPolyline(line, cum, s, total), pieceCount);
  append(out.points, last);
  out.sewnLength += polylineLength(last);
  return out;
}

void append(Polyline& out, const Point2& p) {
  if (out.empty() || (out.back() - p).norm() > 1e-9)
    out.push_back(p);
}

void append(Polyline& out, const Polyline& pts) {
  for (const auto& p : pts)
    append(out, p);
}

Panel makePanel(const std::string& name, Polyline outline) {
  if (outline.size() > 1 && (outline.front() - outline.back()).norm() < 1e-9)
    outline.pop_back();
  if (signedArea(outline) > 0) {
    std::reverse(outline.begin() + 1, outline.end());
  }
  Panel p;
  p.name = name;
  p.outline = std::move(outline);
  return p;
}

int vertexIndex(const Panel& panel, const Point2& p) {
  for (std::size_t i = 0; i < panel.outline.size(); ++i) {
    if ((panel.outline[i] - p).norm() < 1e-6)
      return static_cast<int>(i);
  }
  throw std::logic_error("panel '" + panel.name + "' has no vertex at (" + std::to_string(p.x()) +
                         ", " + std::to_string(p.y()) + ")");
}

namespace {

// polylineLength(edgePoints(panel, e)), the same sum, without copying the points.
double edgeLength(const Panel& panel, const EdgeRef& e) {
  const int n = static_cast<int>(panel.outline.size());
  double total = 0;
  for (int i = e.from; i != e.to;) {
    const int next = (i + 1) % n;
    total +=
        (panel.outline[static_cast<std::size_t>(next)] - panel.outline[static_cast<std::size_t>(i)])
            .norm();
    i = next;
  }
  return total;
}

}  // namespace

EdgeRef shortEdge(const Panel& panel, const Point2& p1, const Point2& p2) {
  const EdgeRef forward{panel.name, vertexIndex(panel, p1), vertexIndex(panel, p2)};
  const EdgeRef backward{panel.name, forward.to, forward.from};
  return edgeLength(panel, forward) <= edgeLength(panel, backward) ? forward : backward;
}

void addSeam(Pattern& pattern, const std::string& name, const std::string& a, const Point2& a1,
             const Point2& a2, const std::string& b, const Point2& b1, const Point2& b2,
             double ease, bool sameDirection) {
  const Panel& pa = pattern.panel(a);
  const Panel& pb = pattern.panel(b);
  EdgeRef ea = shortEdge(pa, a1, a2);
  EdgeRef eb = shortEdge(pb, b1, b2);
  // Convention a.from <-> b.to: when a walks a1 -> a2, b must walk b2 -> b1.
  const bool aForward = ea.from == vertexIndex(pa, a1);
  const bool bForward = eb.from == vertexIndex(pb, b1);
  if ((aForward == bForward) != sameDirection) {
    // Only a distorted outline (absurd measurements) turns a panel round: refuse the body.
    throw DraftError("recipe '" + pattern.type + "': seam '" + name + "': panels '" + a +
                     "' and '" + b + "' do not fit together (an outline turned over)");
  }
  pattern.seams.push_back(SeamPair{name, ea, eb, ease});
}

Polyline edgePoints(const Panel& panel, const EdgeRef& e) {
  Polyline out;
  const int n = static_cast<int>(panel.outline.size());
  for (int i = e.from;; i = (i + 1) % n) {
    out.push_back(panel.outline[static_cast<std::size_t>(i)]);
    if (i == e.to)
      break;
  }
  return out;
}

void addPanelWithRegion(Pattern& pattern, Panel panel) {
  panel.draftRegions = {panel.name};
  pattern.regions.push_back(DraftRegion{panel.name, panel.outline});
  pattern.panels.push_back(std::move(panel));
}

Grainline grainline(const Point2& a, const Point2& b) {
  return Grainline{pointAtFraction(a, b, 0.1), pointAtFraction(a, b, 0.9)};
}

Point2 pointAlong(const Polyline& pl, double s) {
  return drafts::pointAtLength(pl, s);
}

void addDoubleNotch(Panel& panel, const std::string& name, const Polyline& pl, double s) {
  panel.notches.push_back(Notch{name, pointAlong(pl, s)});
  panel.notches.push_back(Notch{name + "_2", pointAlong(pl, s - kDoubleNotchGapCm)});
}

namespace {

Panel& mutablePanel(Pattern& pattern, const std::string& name) {
  for (auto& panel : pattern.panels)
    if (panel.name == name)
      return panel;
  throw std::logic_error("no panel '" + name + "' for a seam notch");
}

// The points of a seam edge from the given end, with for each segment whether it is sewn (a
// segment with a dart apex at one end is a dart leg: its opening is closed, not sewn along).
struct SewnPath {
  Polyline points;
  std::vector<bool> sewn;
  double length = 0;
};

SewnPath sewnPath(const Panel& panel, const EdgeRef& e, bool fromEnd) {
  SewnPath path;
  path.points = edgePoints(panel, e);
  if (fromEnd)
    std::reverse(path.points.begin(), path.points.end());
  const auto isApex = [&](const Point2& q) {
    return std::any_of(panel.darts.begin(), panel.darts.end(),
                       [&](const Dart& d) { return (d.apex - q).norm() < 1e-6; });
  };
  for (size_t i = 0; i + 1 < path.points.size(); ++i) {
    const bool sewn = !isApex(path.points[i]) && !isApex(path.points[i + 1]);
    path.sewn.push_back(sewn);
    if (sewn)
      path.length += (path.points[i + 1] - path.points[i]).norm();
  }
  return path;
}

Point2 pointAtSewn(const SewnPath& path, double distance) {
  double s = 0;
  for (size_t i = 0; i < path.sewn.size(); ++i) {
    if (!path.sewn[i])
      continue;
    const Point2 a = path.points[i], b = path.points[i + 1];
    const double len = (b - a).norm();
    if (s + len >= distance && len > 0)
      return a + (b - a) * ((distance - s) / len);
    s += len;
  }
  return path.points.back();
}

}  // namespace

void addSeamNotches(Pattern& pattern, const std::string& seamName, const std::string& name,
                    double fraction) {
  const auto seam = std::find_if(pattern.seams.begin(), pattern.seams.end(),
                                 [&](const SeamPair& s) { return s.name == seamName; });
  if (seam == pattern.seams.end())
    throw std::logic_error("no seam '" + seamName + "' to notch");
  Panel& a = mutablePanel(pattern, seam->a.panel);
  Panel& b = mutablePanel(pattern, seam->b.panel);
  // a.from meets b.to (b.from when the outlines run the same way along the seam).
  const SewnPath pa = sewnPath(a, seam->a, false);
  const SewnPath pb = sewnPath(b, seam->b, !seamRunsSameWay(*seam));
  const double distance = fraction * std::min(pa.length, pb.length);
  a.notches.push_back(Notch{name, pointAtSewn(pa, distance)});
  b.notches.push_back(Notch{name, pointAtSewn(pb, distance)});
}

}  // namespace garmcap::drafts::detail
