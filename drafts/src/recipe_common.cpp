#include "recipe_common.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

}  // namespace garmcap::drafts::detail
