// Pattern pieces as SVG at 1:1 in millimetres.
#include "garmcap/drafts/export_svg.h"

#include <sstream>

#include "export_util.h"
#include "garmcap/drafts/xml_escape.h"

namespace garmcap::drafts {

using detail::asciiText;
using detail::blockName;
using detail::Box;
using detail::fixed;
using detail::inwardNormal;
using detail::panelBox;

std::string patternSvg(const Pattern& pattern, const PieceText& text) {
  detail::checkPattern<SvgExportError>(pattern);
  const detail::CutSheet sheet = detail::cutSheet<SvgExportError>(pattern, 2.0, 160.0);
  const Layout& lay = sheet.layout;
  const double extraCm = 2.0;  // title line
  std::ostringstream os;
  auto pt = [](const Point2& p) { return fixed(p.x() * 10, 2) + "," + fixed(p.y() * 10, 2); };
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fixed(lay.widthCm * 10, 2)
     << "mm\" height=\"" << fixed((lay.heightCm + extraCm) * 10, 2) << "mm\" viewBox=\"0 0 "
     << fixed(lay.widthCm * 10, 2) << " " << fixed((lay.heightCm + extraCm) * 10, 2) << "\">\n"
     << "<title>" << xmlEscape(text.style + " " + pattern.type + " size " + text.size)
     << "</title>\n"
     << "<style>.cut{fill:#fdfcf8;stroke:#111;stroke-width:0.5}.dart{fill:none;stroke:#c33;"
        "stroke-width:0.4;stroke-dasharray:3 2}.int{fill:none;stroke:#36c;stroke-width:0.4;"
        "stroke-dasharray:4 2}.grain{stroke:#111;stroke-width:0.4}.notch{stroke:#111;"
        "stroke-width:0.6}.sew{fill:none;stroke:#111;stroke-width:0.35;stroke-dasharray:4 2}"
        ".fold{fill:none;stroke:#111;stroke-width:0.4}text{font-family:sans-serif;fill:#111}</"
        "style>\n";
  os << "<text x=\"20\" y=\"" << fixed((lay.heightCm + 1.2) * 10, 2) << "\" font-size=\"5\">"
     << xmlEscape(text.style + " · " + pattern.type + " · size " + text.size +
                  " · 1:1, units mm · cut line (solid) " +
                  detail::allowanceNote(pattern.panels.front()) + " · sew line dashed")
     << "</text>\n";
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    const auto& p = pattern.panels[i];
    const Point2 off = lay.offsets[i];
    auto q = [&](const Point2& a) { return pt(a + off); };
    const Polyline& cutLine = sheet.cuts[i];
    os << "<g id=\"" << xmlEscape(p.name) << "\">\n<polygon class=\"cut\" points=\"";
    for (size_t k = 0; k < cutLine.size(); ++k)
      os << (k ? " " : "") << q(cutLine[k]);
    os << "\"/>\n<polygon class=\"sew\" points=\"";
    for (size_t k = 0; k < p.outline.size(); ++k)
      os << (k ? " " : "") << q(p.outline[k]);
    os << "\"/>\n";
    if (const auto fold = detail::foldMark(p, pattern)) {
      auto polyline = [&](const Polyline& pl) {
        os << "<polyline class=\"fold\" points=\"";
        for (size_t k = 0; k < pl.size(); ++k)
          os << (k ? " " : "") << q(pl[k]);
        os << "\"/>\n";
      };
      polyline(fold->bracket);
      for (const auto& arrow : fold->arrows)
        polyline(arrow);
      const Point2 at = fold->label + off;
      os << "<text class=\"foldlabel\" x=\"" << fixed(at.x() * 10, 2) << "\" y=\""
         << fixed(at.y() * 10, 2) << "\" font-size=\"5\" transform=\"rotate("
         << fixed(fold->labelAngleDeg, 2) << " " << fixed(at.x() * 10, 2) << " "
         << fixed(at.y() * 10, 2) << ")\">PLACE ON FOLD</text>\n";
    }
    for (const auto& d : p.darts)
      os << "<polyline class=\"dart\" points=\"" << q(d.leg1) << " " << q(d.apex) << " "
         << q(d.leg2) << "\"/>\n";
    for (const auto& l : p.internalLines) {
      os << "<polyline class=\"int\" points=\"";
      for (size_t k = 0; k < l.points.size(); ++k)
        os << (k ? " " : "") << q(l.points[k]);
      os << "\"/>\n";
    }
    for (const auto& n : p.notches) {
      const auto slit = detail::notchSlit(p.outline, cutLine, n.position);
      os << "<line class=\"notch\" x1=\"" << fixed((slit.from + off).x() * 10, 2) << "\" y1=\""
         << fixed((slit.from + off).y() * 10, 2) << "\" x2=\"" << fixed((slit.to + off).x() * 10, 2)
         << "\" y2=\"" << fixed((slit.to + off).y() * 10, 2) << "\"/>\n";
    }
    // Grainline with an arrowhead at each end.
    Point2 a = p.grainline.start + off, b = p.grainline.end + off;
    os << "<line class=\"grain\" x1=\"" << fixed(a.x() * 10, 2) << "\" y1=\""
       << fixed(a.y() * 10, 2) << "\" x2=\"" << fixed(b.x() * 10, 2) << "\" y2=\""
       << fixed(b.y() * 10, 2) << "\"/>\n";
    if ((b - a).norm() > 0) {
      Point2 u = (b - a).normalized(), v(-u.y(), u.x());
      for (const auto& [tip, dir] : {std::pair{b, u}, std::pair{a, Point2(-u)}}) {
        Point2 l = tip - 0.8 * dir + 0.3 * v, r = tip - 0.8 * dir - 0.3 * v;
        os << "<polyline class=\"grain\" fill=\"none\" points=\"" << pt(l) << " " << pt(tip) << " "
           << pt(r) << "\"/>\n";
      }
    }
    Box bx = panelBox(p);
    Point2 c = (bx.min + bx.max) / 2 + off;
    std::string cut = "Cut " + std::to_string(p.cutCount) + (p.cutOnFold ? " on fold" : "");
    os << "<text x=\"" << fixed(c.x() * 10, 2) << "\" y=\"" << fixed(c.y() * 10 - 4, 2)
       << "\" font-size=\"7\" text-anchor=\"middle\">" << xmlEscape(pieceTitle(p.name))
       << "</text>\n"
       << "<text x=\"" << fixed(c.x() * 10, 2) << "\" y=\"" << fixed(c.y() * 10 + 5, 2)
       << "\" font-size=\"5\" text-anchor=\"middle\">"
       << xmlEscape("size " + text.size + " · " + cut) << "</text>\n</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace garmcap::drafts
