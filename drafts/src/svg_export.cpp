// SVG at true scale: the user unit is 1 cm (viewBox in cm, width/height in cm), so stroke
// widths and font sizes below are in cm too.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "export_util.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/seam_allowance.h"
#include "garmcap/drafts/svg.h"
#include "garmcap/drafts/xml_escape.h"

namespace garmcap::drafts {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << (std::abs(v) < 5e-4 ? 0.0 : v);
  return s.str();
}

std::string pointsAttr(const Polyline& pl) {
  std::string s;
  for (const auto& p : pl)
    s += num(p.x()) + "," + num(p.y()) + " ";
  if (!s.empty())
    s.pop_back();
  return s;
}

struct Box {
  double x0 = std::numeric_limits<double>::max(), y0 = x0;
  double x1 = -std::numeric_limits<double>::max(), y1 = x1;
  void add(const Point2& p) {
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  void add(const Polyline& pl) {
    for (const auto& p : pl)
      add(p);
  }
  bool empty() const { return x0 > x1; }
};

// The cut line of each panel (seam allowance included, the same offset the DXF-AAMA layer 1
// holds), or nothing for a panel whose cut line cannot be built: that panel is drawn with its
// sew line only and the reason is written beside it, rather than failing the whole drawing.
struct CutLine {
  std::optional<Polyline> line;
  std::string why;
};

CutLine cutLineOf(const Panel& panel, const Pattern& pattern) {
  try {
    return {cutOutline(panel, pattern), {}};
  } catch (const SeamAllowanceError& e) {
    return {std::nullopt, e.what()};
  }
}

}  // namespace

std::string patternToSvg(const Pattern& pattern, const SvgOptions& options) {
  Box box;
  if (options.drawDraft) {
    for (const auto& l : pattern.lines)
      box.add(l.points);
  }
  std::vector<CutLine> cuts;
  for (const auto& p : pattern.panels) {
    box.add(p.outline);
    if (options.drawPanels) {
      cuts.push_back(cutLineOf(p, pattern));
      if (cuts.back().line)
        box.add(*cuts.back().line);
    }
  }
  if (box.empty()) {
    box.add(Point2(0, 0));
    box.add(Point2(10, 10));
  }
  const double m = options.marginCm;
  const double titleH = 4.0;
  const double x0 = box.x0 - m, y0 = box.y0 - m - titleH;
  const double w = box.x1 - box.x0 + 2 * m, h = box.y1 - box.y0 + 2 * m + titleH + 2.0;
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << num(w)
    << "cm\" height=\"" << num(h) << "cm\" viewBox=\"" << num(x0) << " " << num(y0) << " " << num(w)
    << " " << num(h) << "\">\n";
  s << "<title>" << xmlEscape(pattern.type) << " draft (1 user unit = 1 cm)</title>\n";
  s << "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"6\" "
       "markerHeight=\"6\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" "
       "fill=\"#1f5fa8\"/></marker></defs>\n";
  s << "<rect x=\"" << num(x0) << "\" y=\"" << num(y0) << "\" width=\"" << num(w) << "\" height=\""
    << num(h) << "\" fill=\"white\"/>\n";
  // Title: type and the body.
  std::string body;
  for (const auto& [k, v] : pattern.measurements.values())
    body += k + " " + num(v).substr(0, num(v).size() - 2) + "  ";
  s << "<g font-family=\"sans-serif\" fill=\"black\">\n"
    << "<text x=\"" << num(x0 + 1) << "\" y=\"" << num(y0 + 1.6) << "\" font-size=\"1.2\">"
    << xmlEscape(pattern.type)
    << (options.drawDraft ? " — draft (grey: construction, black: contour), panels (blue)"
                          : " — pieces (cut line solid, sew line dashed)")
    << "</text>\n"
    << "<text x=\"" << num(x0 + 1) << "\" y=\"" << num(y0 + 3.0) << "\" font-size=\"0.7\">"
    << xmlEscape(body) << "</text>\n</g>\n";

  if (options.drawPanels) {
    s << "<g id=\"panels\">\n";
    for (std::size_t i = 0; i < pattern.panels.size(); ++i) {
      const Panel& p = pattern.panels[i];
      s << "<g id=\"panel-" << xmlEscape(p.name) << "\">\n";
      // The cut line (solid) under the sew line (dashed): the fabric is cut on the first and
      // sewn on the second, as DXF-AAMA layers 1 and 14.
      if (cuts[i].line)
        s << "<polygon class=\"cut-line\" points=\"" << pointsAttr(*cuts[i].line)
          << "\" fill=\"#4a90d9\" fill-opacity=\"0.06\" stroke=\"#111\" stroke-width=\"0.06\"/>\n";
      s << "<polygon class=\"sew-line\" points=\"" << pointsAttr(p.outline)
        << "\" fill=\"#4a90d9\" fill-opacity=\"0.13\" stroke=\"#1f5fa8\" stroke-width=\"0.05\" "
           "stroke-dasharray=\"0.4 0.25\"/>\n";
      for (const auto& d : p.darts) {
        // The sewn legs (dartPath): a dart that bends along the outline is drawn as it is sewn.
        s << "<polyline class=\"dart\" points=\"" << pointsAttr(dartPath(p, d))
          << "\" fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"0.04\" stroke-dasharray=\"0.3 "
             "0.2\"/>\n";
        s << "<line x1=\"" << num((d.leg1.x() + d.leg2.x()) / 2) << "\" y1=\""
          << num((d.leg1.y() + d.leg2.y()) / 2) << "\" x2=\"" << num(d.apex.x()) << "\" y2=\""
          << num(d.apex.y()) << "\" stroke=\"#1f5fa8\" stroke-width=\"0.02\" "
          << "stroke-dasharray=\"0.1 0.15\"/>\n";
      }
      for (const auto& l : p.internalLines) {
        s << "<polyline points=\"" << pointsAttr(l.points)
          << "\" fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"0.03\" stroke-dasharray=\"0.5 "
             "0.3\"/>\n";
      }
      s << "<line x1=\"" << num(p.grainline.start.x()) << "\" y1=\"" << num(p.grainline.start.y())
        << "\" x2=\"" << num(p.grainline.end.x()) << "\" y2=\"" << num(p.grainline.end.y())
        << "\" stroke=\"#1f5fa8\" stroke-width=\"0.06\" marker-start=\"url(#arrow)\" "
        << "marker-end=\"url(#arrow)\"/>\n";
      for (const auto& n : p.notches) {
        // A 0.8 cm tick across the outline at the notch.
        const Polyline closed = joined(p.outline, Polyline{p.outline.front()});
        const ClosestPoint cp = closestPoint(closed, n.position);
        const auto t = tangentAtLength(closed, cp.s);
        const Point2 nrm = perpendicularVector(t.value_or(Point2(1, 0)));
        const Point2 a = n.position + 0.4 * nrm, b = n.position - 0.4 * nrm;
        s << "<line x1=\"" << num(a.x()) << "\" y1=\"" << num(a.y()) << "\" x2=\"" << num(b.x())
          << "\" y2=\"" << num(b.y()) << "\" stroke=\"#c0392b\" stroke-width=\"0.08\"/>\n";
      }
      const Point2 c = detail::labelPoint(p.outline);
      const std::string cut = "cut " + std::to_string(p.cutCount) +
                              (p.cutOnFold ? " on fold" : "") + ", SA " +
                              num(p.seamAllowanceCm).substr(0, 4) + " cm";
      s << "<text x=\"" << num(c.x()) << "\" y=\"" << num(c.y() - 0.4)
        << "\" font-family=\"sans-serif\" font-size=\"1.1\" text-anchor=\"middle\" "
           "fill=\"#1f5fa8\">"
        << xmlEscape(pieceTitle(p.name)) << "</text>\n";
      s << "<text x=\"" << num(c.x()) << "\" y=\"" << num(c.y() + 0.9)
        << "\" font-family=\"sans-serif\" font-size=\"0.7\" text-anchor=\"middle\" "
           "fill=\"#1f5fa8\">"
        << xmlEscape(cut) << "</text>\n";
      if (!cuts[i].line)
        s << "<text x=\"" << num(c.x()) << "\" y=\"" << num(c.y() + 1.8)
          << "\" font-family=\"sans-serif\" font-size=\"0.6\" text-anchor=\"middle\" "
             "fill=\"#c0392b\">"
          << xmlEscape("no cut line: " + cuts[i].why) << "</text>\n";
      s << "</g>\n";
    }
    s << "</g>\n";
  }
  if (options.drawDraft) {
    s << "<g id=\"draft-construction\" fill=\"none\" stroke=\"#9a9a9a\" stroke-width=\"0.03\">\n";
    for (const auto& l : pattern.lines) {
      if (l.construction)
        s << "<polyline points=\"" << pointsAttr(l.points) << "\"/>\n";
    }
    s << "</g>\n<g id=\"draft-contours\" fill=\"none\" stroke=\"black\" stroke-width=\"0.07\" "
         "stroke-linejoin=\"round\">\n";
    for (const auto& l : pattern.lines) {
      if (!l.construction)
        s << "<polyline points=\"" << pointsAttr(l.points) << "\"/>\n";
    }
    s << "</g>\n";
    if (options.drawPointNames) {
      s << "<g font-family=\"sans-serif\" font-size=\"0.45\" fill=\"#555\">\n";
      for (const auto& [name, p] : pattern.points) {
        s << "<circle cx=\"" << num(p.x()) << "\" cy=\"" << num(p.y()) << "\" r=\"0.12\"/>"
          << "<text x=\"" << num(p.x() + 0.2) << "\" y=\"" << num(p.y() - 0.2) << "\">"
          << xmlEscape(name) << "</text>\n";
      }
      s << "</g>\n";
    }
  }
  // 10 cm scale bar under the drawing, to check the print scale.
  const double by = box.y1 + m;
  s << "<g stroke=\"black\" stroke-width=\"0.05\"><line x1=\"" << num(box.x0) << "\" y1=\""
    << num(by) << "\" x2=\"" << num(box.x0 + 10) << "\" y2=\"" << num(by) << "\"/>";
  for (int i = 0; i <= 10; ++i) {
    s << "<line x1=\"" << num(box.x0 + i) << "\" y1=\"" << num(by - (i % 5 ? 0.2 : 0.4))
      << "\" x2=\"" << num(box.x0 + i) << "\" y2=\"" << num(by) << "\"/>";
  }
  s << "</g><text x=\"" << num(box.x0 + 10.5) << "\" y=\"" << num(by)
    << "\" font-family=\"sans-serif\" font-size=\"0.7\">10 cm</text>\n";
  if (options.drawPanels && !pattern.panels.empty()) {
    // Legend: which line is cut and which is sewn, and the allowance between them.
    const double lx = box.x0 + 14;
    s << "<g id=\"legend\" font-family=\"sans-serif\" font-size=\"0.7\">"
      << "<line x1=\"" << num(lx) << "\" y1=\"" << num(by - 0.25) << "\" x2=\"" << num(lx + 2)
      << "\" y2=\"" << num(by - 0.25) << "\" stroke=\"#111\" stroke-width=\"0.06\"/>"
      << "<text x=\"" << num(lx + 2.4) << "\" y=\"" << num(by) << "\">"
      << xmlEscape("cut line (" + detail::allowanceNote(pattern.panels.front()) + ")")
      << "</text><line x1=\"" << num(lx) << "\" y1=\"" << num(by + 0.95) << "\" x2=\""
      << num(lx + 2) << "\" y2=\"" << num(by + 0.95)
      << "\" stroke=\"#1f5fa8\" stroke-width=\"0.05\" stroke-dasharray=\"0.4 0.25\"/>"
      << "<text x=\"" << num(lx + 2.4) << "\" y=\"" << num(by + 1.2)
      << "\">sew line (net outline)</text></g>\n";
  }
  s << "</svg>\n";
  return s.str();
}

void writePatternSvg(const std::filesystem::path& path, const Pattern& pattern,
                     const SvgOptions& options) {
  writeFileAtomic(path, patternToSvg(pattern, options));
}

}  // namespace garmcap::drafts
