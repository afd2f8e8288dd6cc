// Shared by the pattern file writers; see export_util.h.
#include "export_util.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/seam_allowance.h"

namespace garmcap::drafts::detail {
namespace {

constexpr double kOnVertexCm = 0.02;  // a dart leg or notch this close to a vertex is on it

// Area centroid of a polygon (falls back to the vertex mean for degenerate input).
Point2 centroid(const Polyline& poly) {
  double a = 0;
  Point2 c(0, 0);
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point2& p = poly[i];
    const Point2& q = poly[(i + 1) % poly.size()];
    const double cross = p.x() * q.y() - q.x() * p.y();
    a += cross;
    c += (p + q) * cross;
  }
  if (std::abs(a) < 1e-9) {
    Point2 m(0, 0);
    for (const auto& p : poly)
      m += p;
    return m / static_cast<double>(std::max<std::size_t>(poly.size(), 1));
  }
  return c / (3 * a);
}

}  // namespace

Point2 labelPoint(const Polyline& outline) {
  Point2 c = centroid(outline);
  if (pointInPolygon(c, outline))
    return c;
  auto hits =
      intersectPolylineLine(joined(outline, Polyline{outline.front()}), Line::horizontal(c.y()));
  std::vector<double> xs;
  for (const auto& h : hits)
    xs.push_back(h.point.x());
  std::sort(xs.begin(), xs.end());
  double best = -1;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
    if (xs[i + 1] - xs[i] > best) {
      best = xs[i + 1] - xs[i];
      c.x() = (xs[i] + xs[i + 1]) / 2;
    }
  }
  return c;
}

std::string fixed(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.size() > 1 && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos)
    s.erase(0, 1);
  return s;
}

std::string asciiText(const std::string& s) {
  std::string out;
  for (unsigned char c : s)
    out += (c >= 32 && c < 127) ? static_cast<char>(c) : '_';
  return out;
}

std::string blockName(const std::string& piece, const std::string& size) {
  std::string out;
  for (unsigned char c : piece + "_" + size)
    out += (std::isalnum(c) || c == '_' || c == '-') ? static_cast<char>(c) : '-';
  return out;
}

Box panelBox(const Panel& p) {
  Box b;
  b.add(p.outline);
  return b;
}

int nearestVertex(const Polyline& outline, const Point2& p) {
  int best = -1;
  double bestD = kOnVertexCm;
  for (size_t i = 0; i < outline.size(); ++i) {
    double d = (outline[i] - p).norm();
    if (d <= bestD) {
      bestD = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

Point2 inwardNormal(const Polyline& outline, const Point2& p) {
  size_t bestI = 0;
  double bestD = 1e300;
  for (size_t i = 0; i < outline.size(); ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % outline.size()];
    Point2 ab = b - a;
    double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0;
    double d = (a + t * ab - p).norm();
    if (d < bestD) {
      bestD = d;
      bestI = i;
    }
  }
  Point2 e = outline[(bestI + 1) % outline.size()] - outline[bestI];
  if (e.norm() == 0)
    return Point2(0, 0);
  e.normalize();
  // With positive shoelace area the interior lies to the left of each edge: (-ey, ex).
  Point2 left(-e.y(), e.x());
  return signedArea(outline) >= 0 ? left : Point2(-left);
}

template <class E>
void checkPanel(const Panel& p) {
  if (p.outline.size() < 3)
    throw E("panel '" + p.name + "': outline has " + std::to_string(p.outline.size()) +
            " points; a piece needs at least 3");
  for (const auto& q : p.outline)
    if (!std::isfinite(q.x()) || !std::isfinite(q.y()))
      throw E("panel '" + p.name + "': outline has a non-finite coordinate");
}

template <class E>
void checkPattern(const Pattern& p) {
  if (p.panels.empty())
    throw E("pattern '" + p.type + "' has no panels");
  for (const auto& panel : p.panels)
    checkPanel<E>(panel);
}

template <class E>
Polyline cutLine(const Panel& p, const Pattern& pattern) {
  try {
    return cutOutline(p, pattern);
  } catch (const SeamAllowanceError& e) {
    throw E(e.what());
  }
}

template <class E>
CutSheet cutSheet(const Pattern& pattern, double gapCm, double maxRowWidthCm) {
  CutSheet sheet;
  Pattern cut = pattern;
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    sheet.cuts.push_back(cutLine<E>(pattern.panels[i], pattern));
    cut.panels[i].outline = sheet.cuts.back();
  }
  sheet.layout = layoutPanels(cut, gapCm, maxRowWidthCm);
  return sheet;
}

NotchSlit notchSlit(const Polyline& outline, const Polyline& cut, const Point2& notch) {
  constexpr double kSlitCm = 0.5;
  const Point2 in = inwardNormal(outline, notch);
  // The first crossing of the cut line going out from the notch (none on a fold: the notch).
  Point2 from = notch;
  double best = 1e300;
  for (const auto& hit :
       intersectPolylineLine(joined(cut, Polyline{cut.front()}), Line{notch, Point2(-in)})) {
    const double t = (hit.point - notch).dot(-in);
    if (t >= -kGeometryEpsCm && t < best) {
      best = t;
      from = hit.point;
    }
  }
  return {from, from + kSlitCm * in};
}

std::optional<FoldMark> foldMark(const Panel& p, const Pattern& pattern) {
  const auto fold = foldEdge(p, pattern);
  if (!fold)
    return std::nullopt;
  FoldMark m;
  m.foldStart = p.outline[static_cast<size_t>(fold->from)];
  m.foldEnd = p.outline[static_cast<size_t>(fold->to)];
  const Point2 along = m.foldEnd - m.foldStart;
  if (along.norm() < 1.0)
    return std::nullopt;
  const Point2 u = along.normalized();
  const Point2 in = inwardNormal(p.outline, (m.foldStart + m.foldEnd) / 2);
  constexpr double kInsideCm = 2.0, kArrowCm = 0.6;
  const Point2 a = m.foldStart + 0.15 * along, b = m.foldStart + 0.85 * along;
  m.bracket = {a, a + kInsideCm * in, b + kInsideCm * in, b};
  for (const Point2& tip : {a, b})
    m.arrows.push_back({tip + kArrowCm * in + 0.3 * u, tip, tip + kArrowCm * in - 0.3 * u});
  // Text just inside the bracket's long side, reading downward or upward along the fold so
  // that it is never upside down (angle in (-90, 90]).
  Point2 dir = u;
  if (dir.x() < -1e-9 || (std::abs(dir.x()) <= 1e-9 && dir.y() < 0))
    dir = -dir;
  m.labelAngleDeg = std::atan2(dir.y(), dir.x()) * 180.0 / 3.14159265358979323846;
  const Point2 centre = (a + b) / 2 + (kInsideCm + 0.4) * in;
  m.label = centre - 2.2 * dir;
  return m;
}

std::string allowanceNote(const Panel& p) {
  return "seam allowance " + fixed(p.seamAllowanceCm * 10, 1) + " mm included, hem " +
         fixed(kHemAllowanceCm * 10, 1) + " mm, none on fold";
}

#define GARMCAP_EXPORT_CHECKS(E)                                        \
  template void checkPanel<E>(const Panel& p);                          \
  template void checkPattern<E>(const Pattern& p);                      \
  template Polyline cutLine<E>(const Panel& p, const Pattern& pattern); \
  template CutSheet cutSheet<E>(const Pattern& pattern, double gapCm, double maxRowWidthCm);
GARMCAP_EXPORT_CHECKS(PatternExportError)
GARMCAP_EXPORT_CHECKS(DxfExportError)
GARMCAP_EXPORT_CHECKS(RulExportError)
GARMCAP_EXPORT_CHECKS(GarmentCodeExportError)
GARMCAP_EXPORT_CHECKS(PdfExportError)
GARMCAP_EXPORT_CHECKS(SvgExportError)
GARMCAP_EXPORT_CHECKS(SeamAllowanceError)
#undef GARMCAP_EXPORT_CHECKS

}  // namespace garmcap::drafts::detail
