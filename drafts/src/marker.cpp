// Markers: pieces prepared for the fabric, nested by libnest2d, written as SVG, PDF and DXF.
#include "garmcap/drafts/marker.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "dxf_r12.h"
#include "export_util.h"
#include "garmcap/drafts/geometry_polygon.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/xml_escape.h"
#include "nesting_libnest2d.h"
#include "pdf_document.h"
#include "size_styles.h"

namespace garmcap::drafts {
namespace {

using detail::fixed;

constexpr double kOnFoldCm = 0.05;       // a cut-line vertex this near the fold edge lies on it
constexpr double kFoldStraightCm = 0.1;  // a fold edge this far off its chord cannot be opened

Point2 reflect(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 u = (b - a).normalized();
  const Point2 d = p - a;
  return a + 2 * d.dot(u) * u - d;
}

double distToLine(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 u = (b - a).normalized();
  const Point2 d = p - a;
  return std::abs(d.x() * u.y() - d.y() * u.x());
}

// The cut line opened out about the fold: the cut line from the fold's far end round to its near
// end, then the same path mirrored about the fold line, back.
Polyline unfold(const Panel& p, const Pattern& pattern, const Polyline& cut) {
  const auto edge = foldEdge(p, pattern);
  if (!edge)
    return cut;
  const Point2 a = p.outline[static_cast<size_t>(edge->from)];
  const Point2 b = p.outline[static_cast<size_t>(edge->to)];
  const size_t n = p.outline.size();
  for (size_t i = static_cast<size_t>(edge->from);; i = (i + 1) % n) {
    const double off = distToLine(p.outline[i], a, b);
    if (off > kFoldStraightCm)
      throw MarkerError("marker: panel '" + p.name + "': its fold edge leaves the fold line by " +
                        fixed(off, 2) + " cm; it cannot be opened out into one piece");
    if (i == static_cast<size_t>(edge->to))
      break;
  }
  const size_t m = cut.size();
  std::vector<bool> on(m);
  size_t count = 0;
  for (size_t i = 0; i < m; ++i) {
    on[i] = distToLine(cut[i], a, b) < kOnFoldCm;
    count += on[i] ? 1 : 0;
  }
  if (count < 2 || count == m)
    throw MarkerError("marker: panel '" + p.name + "': its cut line does not run along its fold");
  // The first vertex after the fold run (on[i-1] && !on[i]) starts the open path.
  size_t start = m;
  for (size_t i = 0; i < m; ++i)
    if (on[(i + m - 1) % m] && !on[i])
      start = i;
  Polyline path = {cut[(start + m - 1) % m]};  // the fold's end
  for (size_t k = 0, i = start; k < m && !on[i]; ++k, i = (i + 1) % m)
    path.push_back(cut[i]);
  // The fold's other end closes the path.
  for (size_t i = start;; i = (i + 1) % m)
    if (on[i]) {
      path.push_back(cut[i]);
      break;
    }
  Polyline out = path;
  for (size_t k = path.size() - 1; k-- > 1;)
    out.push_back(reflect(path[k], a, b));
  return out;
}

Polyline transformed(const Polyline& pl, double c, double s, const Point2& t) {
  Polyline out;
  for (const auto& p : pl)
    out.push_back(Point2(c * p.x() - s * p.y(), s * p.x() + c * p.y()) + t);
  return out;
}

// The shared checks and cut line, their PatternExportError told as a MarkerError.
void checkPatternForMarker(const Pattern& p) {
  try {
    detail::checkPattern<PatternExportError>(p);
  } catch (const PatternExportError& e) {
    throw MarkerError(std::string("marker: ") + e.what());
  }
}

Polyline cutLineForMarker(const Panel& p, const Pattern& pattern) {
  try {
    return detail::cutLine<PatternExportError>(p, pattern);
  } catch (const PatternExportError& e) {
    throw MarkerError(std::string("marker: ") + e.what());
  }
}

}  // namespace

Marker layMarker(const std::vector<SizedPattern>& sizes, const MarkerOptions& options) {
  if (sizes.empty())
    throw MarkerError("marker: no pattern given");
  if (!(options.fabricWidthCm > 0) || !(options.gapCm >= 0))
    throw MarkerError("marker: fabric width must be > 0 and the gap >= 0");
  if (options.maxPieces < 1)
    throw MarkerError("marker: the piece limit must be at least 1, got " +
                      std::to_string(options.maxPieces));
  std::vector<MarkerPiece> pieces;
  for (const auto& sized : sizes) {
    checkPatternForMarker(sized.pattern);
    for (const auto& p : sized.pattern.panels) {
      const Point2 g = p.grainline.end - p.grainline.start;
      if (g.norm() < 1e-6)
        throw MarkerError("marker: panel '" + p.name + "' of size " + sized.size +
                          " has no grain line");
      Polyline cut = cutLineForMarker(p, sized.pattern);
      const bool folded = p.cutOnFold && foldEdge(p, sized.pattern).has_value();
      if (folded)
        cut = unfold(p, sized.pattern, cut);
      // Turn the piece so that its grain line runs along +x (the fabric's length).
      const double ang = -std::atan2(g.y(), g.x());
      const double c = std::cos(ang), s = std::sin(ang);
      MarkerPiece base;
      base.panel = p.name;
      base.size = sized.size;
      base.unfolded = folded;
      base.cutLine = transformed(cut, c, s, Point2(0, 0));
      base.grainStart = transformed({p.grainline.start}, c, s, Point2(0, 0))[0];
      base.grainEnd = transformed({p.grainline.end}, c, s, Point2(0, 0))[0];
      base.areaCm2 = polygonArea(base.cutLine);
      for (int k = 0; k < std::max(1, p.cutCount); ++k) {
        MarkerPiece piece = base;
        if (k % 2 == 1) {  // the other half of a pair: mirrored across the grain
          piece.mirrored = true;
          for (auto* q : {&piece.grainStart, &piece.grainEnd})
            q->y() = -q->y();
          for (auto& q : piece.cutLine)
            q.y() = -q.y();
          std::reverse(piece.cutLine.begin(), piece.cutLine.end());
        }
        pieces.push_back(std::move(piece));
      }
    }
  }
  // The limit is checked before nesting, which is where the time goes.
  if (pieces.size() > static_cast<std::size_t>(options.maxPieces))
    throw MarkerLimitError("marker: " + std::to_string(pieces.size()) + " pieces to lay (" +
                           std::to_string(sizes.size()) + " size" + (sizes.size() == 1 ? "" : "s") +
                           "), more than the limit of " + std::to_string(options.maxPieces) +
                           " pieces (max_pieces); lay fewer sizes per marker or raise the limit");
  // Turning by 180 degrees keeps a piece's extent across the grain: one wider than the fabric
  // cannot be laid at all. Said here, where the piece has its name (the nester knows rings).
  for (const auto& p : pieces) {
    double minY = 1e300, maxY = -1e300;
    for (const auto& q : p.cutLine) {
      minY = std::min(minY, q.y());
      maxY = std::max(maxY, q.y());
    }
    if (maxY - minY > options.fabricWidthCm)
      throw MarkerError("marker: panel '" + p.panel + "' of size " + p.size + " is " +
                        fixed(maxY - minY, 2) + " cm across the grain, wider than the fabric (" +
                        fixed(options.fabricWidthCm, 1) + " cm)");
  }
  std::vector<detail::NestRing> rings;
  for (const auto& p : pieces) {
    detail::NestRing r;
    for (const auto& q : p.cutLine)
      r.emplace_back(q.x(), q.y());
    rings.push_back(std::move(r));
  }
  std::vector<detail::NestPlacement> placed;
  try {
    placed = detail::nestInStrip(rings, options.fabricWidthCm, options.gapCm);
  } catch (const std::runtime_error& e) {
    throw MarkerError(std::string("marker: ") + e.what());
  }
  Marker m;
  m.widthCm = options.fabricWidthCm;
  double minX = 1e300, maxX = -1e300;
  for (size_t i = 0; i < pieces.size(); ++i) {
    auto& p = pieces[i];
    const double c = std::cos(placed[i].rotationRad), s = std::sin(placed[i].rotationRad);
    const Point2 t(placed[i].dx, placed[i].dy);
    p.turned = std::abs(placed[i].rotationRad) > 1e-6;
    p.cutLine = transformed(p.cutLine, c, s, t);
    p.grainStart = transformed({p.grainStart}, c, s, t)[0];
    p.grainEnd = transformed({p.grainEnd}, c, s, t)[0];
    for (const auto& q : p.cutLine) {
      minX = std::min(minX, q.x());
      maxX = std::max(maxX, q.x());
      if (q.y() < -1e-3 || q.y() > m.widthCm + 1e-3)
        throw MarkerError("marker: the nester put piece '" + p.panel + "' off the fabric");
    }
  }
  for (auto& p : pieces) {
    for (auto& q : p.cutLine)
      q.x() -= minX;
    p.grainStart.x() -= minX;
    p.grainEnd.x() -= minX;
    m.pieceAreaCm2 += p.areaCm2;
  }
  m.lengthCm = maxX - minX;
  m.efficiency = m.pieceAreaCm2 / (m.lengthCm * m.widthCm);
  m.pieces = std::move(pieces);
  return m;
}

namespace {

std::vector<std::string> sizesOf(const Marker& m) {
  std::vector<std::string> sizes;
  for (const auto& p : m.pieces)
    if (std::find(sizes.begin(), sizes.end(), p.size) == sizes.end())
      sizes.push_back(p.size);
  return sizes;
}

size_t indexOf(const std::vector<std::string>& v, const std::string& s) {
  return static_cast<size_t>(std::find(v.begin(), v.end(), s) - v.begin());
}

std::string summary(const Marker& m) {
  return "marker " + fixed(m.lengthCm, 1) + " cm long on " + fixed(m.widthCm, 1) +
         " cm fabric, efficiency " + fixed(100 * m.efficiency, 1) + " %, " +
         std::to_string(m.pieces.size()) + " pieces";
}

std::string pieceLabel(const MarkerPiece& p) {
  return pieceTitle(p.panel) + " " + p.size + (p.mirrored ? " (mirror)" : "") +
         (p.unfolded ? " (open)" : "");
}

// Grain arrow from grainStart to grainEnd: a line and an arrowhead at each end.
std::vector<Polyline> grainArrow(const MarkerPiece& p) {
  const Point2 a = p.grainStart, b = p.grainEnd;
  std::vector<Polyline> out = {{a, b}};
  if ((b - a).norm() > 1.0) {
    const Point2 u = (b - a).normalized(), v(-u.y(), u.x());
    out.push_back({b - 0.8 * u + 0.3 * v, b, b - 0.8 * u - 0.3 * v});
    out.push_back({a + 0.8 * u + 0.3 * v, a, a + 0.8 * u - 0.3 * v});
  }
  return out;
}

}  // namespace

std::string markerSvg(const Marker& m, const std::string& title) {
  const auto sizes = sizesOf(m);
  const double border = 2.0, header = 3.0 + 0.6 * static_cast<double>(sizes.size());
  const double w = m.lengthCm + 2 * border, h = m.widthCm + header + border;
  auto pt = [&](const Point2& p) {
    return fixed((p.x() + border) * 10, 2) + "," + fixed((p.y() + header) * 10, 2);
  };
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
     << "width=\"" << fixed(w * 10, 2) << "mm\" height=\"" << fixed(h * 10, 2)
     << "mm\" viewBox=\"0 0 " << fixed(w * 10, 2) << " " << fixed(h * 10, 2) << "\">\n"
     << "<title>" << xmlEscape(title + ": " + summary(m)) << "</title>\n"
     << "<style>text{font-family:sans-serif;fill:#111}.fabric{fill:#f6f3ea;stroke:#111;"
        "stroke-width:0.6}.grain{fill:none;stroke:#111;stroke-width:0.4}</style>\n";
  os << "<text x=\"" << fixed(border * 10, 2) << "\" y=\"12\" font-size=\"7\">"
     << xmlEscape(title + ": " + summary(m)) << "</text>\n";
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto st = detail::sizeStyle(i);
    const double y = 20 + 6 * static_cast<double>(i);
    os << "<g class=\"legend\"><rect x=\"" << fixed(border * 10, 2) << "\" y=\"" << fixed(y - 4, 2)
       << "\" width=\"8\" height=\"4\" fill=\"" << st.svgColour << "\" fill-opacity=\"0.35\" "
       << "stroke=\"" << st.svgColour << "\"/><text x=\"" << fixed(border * 10 + 11, 2) << "\" y=\""
       << fixed(y, 2) << "\" font-size=\"5\">size " << xmlEscape(sizes[i]) << "</text></g>\n";
  }
  os << "<rect class=\"fabric\" x=\"" << fixed(border * 10, 2) << "\" y=\"" << fixed(header * 10, 2)
     << "\" width=\"" << fixed(m.lengthCm * 10, 2) << "\" height=\"" << fixed(m.widthCm * 10, 2)
     << "\"/>\n";
  for (const auto& p : m.pieces) {
    const auto st = detail::sizeStyle(indexOf(sizes, p.size));
    os << "<g class=\"piece\" data-panel=\"" << xmlEscape(p.panel) << "\" data-size=\""
       << xmlEscape(p.size) << "\"" << (p.mirrored ? " data-mirrored=\"1\"" : "")
       << "><polygon fill=\"" << st.svgColour << "\" fill-opacity=\"0.35\" stroke=\""
       << st.svgColour << "\" stroke-width=\"0.5\""
       << (st.dashed ? " stroke-dasharray=\"4 2\"" : "") << " points=\"";
    for (size_t k = 0; k < p.cutLine.size(); ++k)
      os << (k ? " " : "") << pt(p.cutLine[k]);
    os << "\"/>\n";
    for (const auto& pl : grainArrow(p)) {
      os << "<polyline class=\"grain\" points=\"";
      for (size_t k = 0; k < pl.size(); ++k)
        os << (k ? " " : "") << pt(pl[k]);
      os << "\"/>\n";
    }
    const Point2 c = detail::labelPoint(p.cutLine);
    os << "<text x=\"" << fixed((c.x() + border) * 10, 2) << "\" y=\""
       << fixed((c.y() + header) * 10 - 3, 2) << "\" font-size=\"5\" text-anchor=\"middle\">"
       << xmlEscape(pieceLabel(p)) << "</text>\n</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

std::string markerPdf(const Marker& m, const std::string& title) {
  using detail::pdfPath;
  const auto sizes = sizesOf(m);
  const double border = 2.0, header = 3.0 + 0.6 * static_cast<double>(sizes.size());
  const double w = m.lengthCm + 2 * border, h = m.widthCm + header + border;
  const Point2 off(border, header);
  auto moved = [&](const Polyline& pl) {
    Polyline out;
    for (const auto& q : pl)
      out.push_back(q + off);
    return out;
  };
  std::ostringstream cs;
  // Sheet coordinates (y down from the top-left corner): one translation to the top.
  cs << "1 0 0 1 0 " << fixed(h * detail::kPtPerCm, 3) << " cm 1 J 1 j 0 G 0 g\n";
  cs << detail::pdfText({border, 1.2}, 11, title + ": " + summary(m));
  cs << "0.8 w\n"
     << pdfPath(moved({{0, 0}, {m.lengthCm, 0}, {m.lengthCm, m.widthCm}, {0, m.widthCm}}), true);
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto st = detail::sizeStyle(i);
    const double y = 2.0 + 0.6 * static_cast<double>(i);
    cs << fixed(st.r, 3) << " " << fixed(st.g, 3) << " " << fixed(st.b, 3) << " RG 1.5 w "
       << pdfPath({{border, y}, {border + 1.0, y}}, false) << "0 g "
       << detail::pdfText({border + 1.3, y + 0.15}, 9, "size " + sizes[i]);
  }
  for (const auto& p : m.pieces) {
    const auto st = detail::sizeStyle(indexOf(sizes, p.size));
    cs << fixed(st.r, 3) << " " << fixed(st.g, 3) << " " << fixed(st.b, 3) << " RG 1 w "
       << (st.dashed ? "[6 3] 0 d\n" : "[] 0 d\n") << pdfPath(moved(p.cutLine), true)
       << "[] 0 d 0 G 0.6 w\n";
    for (const auto& pl : grainArrow(p))
      cs << pdfPath(moved(pl), false);
    const Point2 c = detail::labelPoint(p.cutLine) + off;
    cs << "0 g " << detail::pdfText(c + Point2(-2, -0.3), 8, pieceLabel(p));
  }
  detail::PdfDocument doc;
  doc.addPage(w, h, cs.str());
  return doc.bytes(title);
}

nlohmann::json markerSummaryJson(const Marker& m, const std::string& title) {
  nlohmann::json pieces = nlohmann::json::array();
  for (const auto& p : m.pieces)
    pieces.push_back({{"panel", p.panel},
                      {"size", p.size},
                      {"mirrored", p.mirrored},
                      {"unfolded", p.unfolded},
                      {"turned", p.turned},
                      {"area_cm2", p.areaCm2}});
  return {{"title", title},
          {"fabric_width_cm", m.widthCm},
          {"length_cm", m.lengthCm},
          {"piece_area_cm2", m.pieceAreaCm2},
          {"efficiency", m.efficiency},
          {"sizes", sizesOf(m)},
          {"piece_count", m.pieces.size()},
          {"pieces", pieces}};
}

std::string markerDxf(const Marker& m) {
  const auto sizes = sizesOf(m);
  std::vector<detail::DxfLayer> layers = {
      {"FABRIC", 7, "CONTINUOUS"}, {"GRAIN", 7, "CONTINUOUS"}, {"TEXT", 7, "CONTINUOUS"}};
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto st = detail::sizeStyle(i);
    layers.push_back({"SIZE_" + detail::blockName("", sizes[i]).substr(1), st.aci,
                      st.dashed ? "DASHED" : "CONTINUOUS"});
  }
  detail::DxfR12 d(layers);
  d.polyline("FABRIC", {{0, 0}, {m.lengthCm, 0}, {m.lengthCm, m.widthCm}, {0, m.widthCm}}, true);
  d.text("TEXT", {0, -1.0}, 5.0, summary(m));
  for (const auto& p : m.pieces) {
    const std::string layer = layers[3 + indexOf(sizes, p.size)].name;
    d.polyline(layer, p.cutLine, true);
    for (const auto& pl : grainArrow(p))
      d.polyline("GRAIN", pl, false);
    d.text("TEXT", detail::labelPoint(p.cutLine), 4.0, pieceLabel(p));
  }
  return d.finish();
}

}  // namespace garmcap::drafts
