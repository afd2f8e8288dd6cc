// Tiled pattern PDF (A4, US Letter, A0) at 1:1; see export_pdf.h.
#include "garmcap/drafts/export_pdf.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "export_util.h"
#include "garmcap/drafts/geometry_polygon.h"
#include "pdf_document.h"

namespace garmcap::drafts {
namespace {

using detail::asciiText;
using detail::Box;
using detail::fixed;
using detail::kPtPerCm;
using detail::pdfPath;
using detail::pdfPoint;
using detail::pdfString;
using detail::pdfText;

// A tile of the sheet: the part of it one page's frame shows, in sheet cm.
struct Tile {
  int row = 0, col = 0;
  double x0 = 0, y0 = 0;
};

std::string tileLabel(int row, int col) {
  std::string s;
  for (int r = row;; r = r / 26 - 1) {  // A..Z, AA..
    s.insert(s.begin(), static_cast<char>('A' + r % 26));
    if (r < 26)
      break;
  }
  return s + std::to_string(col + 1);
}

// Liang-Barsky: does segment a-b meet the rectangle [lo, hi]?
bool segmentMeetsRect(const Point2& a, const Point2& b, const Point2& lo, const Point2& hi) {
  double t0 = 0, t1 = 1;
  const Point2 d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - lo.x(), hi.x() - a.x(), a.y() - lo.y(), hi.y() - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0)
        return false;
    } else {
      const double t = q[i] / p[i];
      if (p[i] < 0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1)
        return false;
    }
  }
  return true;
}

// A closed polygon's line or inside reaches into the rectangle.
bool polygonMeetsRect(const Polyline& poly, const Point2& lo, const Point2& hi) {
  for (size_t i = 0; i < poly.size(); ++i)
    if (segmentMeetsRect(poly[i], poly[(i + 1) % poly.size()], lo, hi))
      return true;
  return pointInPolygon((lo + hi) / 2, poly);  // the tile lies wholly inside the piece
}

// A filled dot (four Bezier quarters) and a cross through it: one match mark.
std::string matchMark(const Point2& c, double rCm) {
  const double k = 0.5523 * rCm;
  auto P = [&](double dx, double dy) { return pdfPoint(c + Point2(dx, dy)); };
  std::string s = "1 0 0 rg 1 0 0 RG 0.5 w\n" + P(rCm, 0) + " m " + P(rCm, k) + " " + P(k, rCm) +
                  " " + P(0, rCm) + " c " + P(-k, rCm) + " " + P(-rCm, k) + " " + P(-rCm, 0) +
                  " c " + P(-rCm, -k) + " " + P(-k, -rCm) + " " + P(0, -rCm) + " c " + P(k, -rCm) +
                  " " + P(rCm, -k) + " " + P(rCm, 0) + " c f\n";
  const double L = 2 * rCm;  // stays inside the 1 cm strip (a clipped mark would look off-centre)
  s += P(-L, 0) + " m " + P(L, 0) + " l S " + P(0, -L) + " m " + P(0, L) + " l S\n";
  return s;
}

// The pieces, test square and allowance statement in sheet cm (drawn on every page, clipped).
std::string sheetGeometry(const Pattern& pattern, const PieceText& text,
                          const detail::CutSheet& sheet, const PaperSpec& spec, double shiftY) {
  std::ostringstream geo;
  const double s = spec.testSquareCm;
  geo << "0 0 0 RG 0.8 w 1 J 1 j\n";
  geo << pdfPath({{2, 2}, {2 + s, 2}, {2 + s, 2 + s}, {2, 2 + s}}, true);
  geo << pdfText({2.5, 2 + s * 0.45}, 12, std::string(spec.testSquareLabel) + " test square");
  geo << pdfText({2.5, 2 + s * 0.45 + 0.7}, 9,
                 std::string("must measure ") + spec.testSquareLabel + " x " +
                     spec.testSquareLabel + " (" + fixed(s * 10, 1) + " mm)");
  geo << pdfText({2.5, 2 + s * 0.45 + 1.3}, 9, "print at 100% / actual size");
  geo << pdfText({2.0, 2 + s + 0.8}, 9,
                 "Cut on the solid line: " + detail::allowanceNote(pattern.panels.front()) + ".");
  geo << pdfText({2.0, 2 + s + 1.4}, 9, "Sew on the dashed line (the net seam line).");
  const Point2 shift(0, shiftY);
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    const auto& p = pattern.panels[i];
    const Point2 off = sheet.layout.offsets[i] + shift;
    auto moved = [&](const Polyline& pl) {
      Polyline out;
      for (const auto& q : pl)
        out.push_back(q + off);
      return out;
    };
    const Polyline& cutLine = sheet.cuts[i];
    geo << "1.2 w\n" << pdfPath(moved(cutLine), true);
    geo << "0.6 w [6 3] 0 d\n" << pdfPath(moved(p.outline), true) << "[] 0 d\n";
    if (const auto fold = detail::foldMark(p, pattern)) {
      geo << "0.8 w\n";
      for (const Polyline* pl : {&fold->bracket, &fold->arrows[0], &fold->arrows[1]})
        geo << pdfPath(moved(*pl), false);
      // Text along the fold: PDF angles turn counter-clockwise with y up, ours with y down.
      const double rad = -fold->labelAngleDeg * 3.14159265358979323846 / 180.0;
      geo << "BT /F1 10 Tf " << fixed(std::cos(rad), 6) << " " << fixed(std::sin(rad), 6) << " "
          << fixed(-std::sin(rad), 6) << " " << fixed(std::cos(rad), 6) << " "
          << pdfPoint(fold->label + off) << " Tm " << pdfString("PLACE ON FOLD") << " Tj ET\n";
    }
    geo << "0.6 w [3 2] 0 d\n";
    for (const auto& d : p.darts)
      geo << pdfPath(moved({d.leg1, d.apex, d.leg2}), false);
    for (const auto& l : p.internalLines)
      geo << pdfPath(moved(l.points), false);
    geo << "[] 0 d 0.8 w\n";
    for (const auto& n : p.notches) {
      const auto slit = detail::notchSlit(p.outline, cutLine, n.position);
      geo << pdfPath(moved({slit.from, slit.to}), false);
    }
    // Grain line with an arrowhead at each end (the piece may be turned end for end).
    const Point2 a = p.grainline.start, b = p.grainline.end;
    geo << pdfPath(moved({a, b}), false);
    if ((b - a).norm() > 1.0) {
      const Point2 u = (b - a).normalized(), v(-u.y(), u.x());
      for (const auto& [tip, dir] : {std::pair{b, u}, std::pair{a, Point2(-u)}})
        geo << pdfPath(moved({tip - 0.8 * dir + 0.3 * v, tip, tip - 0.8 * dir - 0.3 * v}), false);
    }
    const Point2 c = detail::labelPoint(p.outline) + off;
    geo << pdfText(c + Point2(-3, 0), 14, pieceTitle(p.name));
    geo << pdfText(c + Point2(-3, 0.7), 10,
                   text.style + "  size " + text.size + "  cut " + std::to_string(p.cutCount) +
                       (p.cutOnFold ? " on fold" : ""));
    geo << pdfText(c + Point2(-3, 1.3), 8, detail::allowanceNote(p));
  }
  return geo.str();
}

}  // namespace

PaperSpec paperSpec(Paper paper) {
  switch (paper) {
    case Paper::kA4:
      return {"A4", 21.0, 29.7};
    case Paper::kLetter:
      return {"US Letter", 21.59, 27.94, 1.0, 1.0, 10.16, "4 in"};
    case Paper::kA0:
      return {"A0", 84.1, 118.9};
  }
  throw std::invalid_argument("unknown paper");
}

Paper parsePaper(const std::string& name) {
  std::string n;
  for (unsigned char c : name)
    n += static_cast<char>(std::tolower(c));
  if (n == "a4")
    return Paper::kA4;
  if (n == "letter" || n == "us-letter")
    return Paper::kLetter;
  if (n == "a0")
    return Paper::kA0;
  throw std::invalid_argument("paper '" + name + "': expected a4, letter or a0");
}

std::string patternPdf(const Pattern& pattern, const PieceText& text, Paper paper) {
  detail::checkPattern<PdfExportError>(pattern);
  const PaperSpec spec = paperSpec(paper);
  const double tileW = spec.widthCm - 2 * spec.marginCm;
  const double tileH = spec.heightCm - 2 * spec.marginCm;
  const double stepX = tileW - spec.overlapCm, stepY = tileH - spec.overlapCm;
  // Office paper: rows about five tiles wide; A0: one frame wide (a wider piece takes a second
  // column).
  const double rowWidth = paper == Paper::kA0 ? tileW : tileW + 4 * stepX;
  const detail::CutSheet sheet = detail::cutSheet<PdfExportError>(pattern, 2.0, rowWidth);
  const Layout& lay = sheet.layout;
  const double shiftY = 2 + spec.testSquareCm + 2.0;  // the test square block above the pieces
  const double sheetW = lay.widthCm, sheetH = lay.heightCm + shiftY;
  const int cols = std::max(1, static_cast<int>(std::ceil((sheetW - spec.overlapCm) / stepX)));
  const int rows = std::max(1, static_cast<int>(std::ceil((sheetH - spec.overlapCm) / stepY)));

  // Tiles with ink: the test square block, or part of a piece's cut line or inside.
  std::vector<Polyline> placed;
  for (size_t i = 0; i < sheet.cuts.size(); ++i) {
    Polyline pl;
    for (const auto& q : sheet.cuts[i])
      pl.push_back(q + lay.offsets[i] + Point2(0, shiftY));
    placed.push_back(std::move(pl));
  }
  std::vector<std::vector<bool>> keep(rows, std::vector<bool>(cols, false));
  std::vector<Tile> tiles;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Point2 lo(c * stepX, r * stepY), hi = lo + Point2(tileW, tileH);
      // A tile's own region leaves out the strips it shares with its left and upper
      // neighbours (those hold the same drawing): the own regions cut the sheet into disjoint
      // parts, so every line is on a page and no page holds only what another one shows.
      const Point2 own = lo + Point2(c > 0 ? spec.overlapCm : 0, r > 0 ? spec.overlapCm : 0);
      bool ink = r == 0 && c == 0;  // the test square block
      for (const auto& pl : placed)
        ink = ink || polygonMeetsRect(pl, own, hi);
      keep[r][c] = ink;
      if (ink)
        tiles.push_back({r, c, lo.x(), lo.y()});
    }
  }
  std::ostringstream marks;
  // Match marks in the strip two kept neighbours share, a quarter and three quarters along it.
  for (const Tile& t : tiles) {
    const std::string here = tileLabel(t.row, t.col);
    if (t.col + 1 < cols && keep[t.row][t.col + 1]) {
      const double x = (t.col + 1) * stepX + spec.overlapCm / 2;
      for (double f : {0.25, 0.75}) {
        const Point2 c(x, t.y0 + f * tileH);
        marks << matchMark(c, 0.2)
              << pdfText(c + Point2(-0.45, 1.0), 7, here + "|" + tileLabel(t.row, t.col + 1));
      }
    }
    if (t.row + 1 < rows && keep[t.row + 1][t.col]) {
      const double y = (t.row + 1) * stepY + spec.overlapCm / 2;
      for (double f : {0.25, 0.75}) {
        const Point2 c(t.x0 + f * tileW, y);
        marks << matchMark(c, 0.2)
              << pdfText(c + Point2(0.7, 0.15), 7, here + "/" + tileLabel(t.row + 1, t.col));
      }
    }
  }
  // Match marks in red: alignment aids, told apart from the pattern's black lines.
  const std::string geometry =
      sheetGeometry(pattern, text, sheet, spec, shiftY) + "1 0 0 rg 1 0 0 RG\n" + marks.str();

  detail::PdfDocument doc;
  const double pt = kPtPerCm, m = spec.marginCm;
  const double ox = m * pt, oy = m * pt, oyTop = (spec.heightCm - m) * pt;
  for (size_t k = 0; k < tiles.size(); ++k) {
    const Tile& t = tiles[k];
    std::ostringstream cs;
    // Tile frame, and the overlap lines where the next tile's frame edge goes.
    cs << "q 0.5 G 0.3 w " << fixed(ox, 3) << " " << fixed(oy, 3) << " " << fixed(tileW * pt, 3)
       << " " << fixed(tileH * pt, 3) << " re S\n1 0 0 RG 0.5 w [2 2] 0 d\n";
    if (t.col + 1 < cols && keep[t.row][t.col + 1]) {
      const double x = ox + (tileW - spec.overlapCm) * pt;
      cs << fixed(x, 3) << " " << fixed(oy, 3) << " m " << fixed(x, 3) << " " << fixed(oyTop, 3)
         << " l S\n";
    }
    if (t.row + 1 < rows && keep[t.row + 1][t.col]) {
      const double y = oy + spec.overlapCm * pt;
      cs << fixed(ox, 3) << " " << fixed(y, 3) << " m " << fixed(ox + tileW * pt, 3) << " "
         << fixed(y, 3) << " l S\n";
    }
    cs << "Q\n";
    auto neighbour = [&](int r, int c) {
      return r >= 0 && c >= 0 && r < rows && c < cols && keep[r][c] ? tileLabel(r, c)
                                                                    : std::string("-");
    };
    const std::string label =
        asciiText(text.style) + " size " + asciiText(text.size) + " - " + spec.name + " p " +
        std::to_string(k + 1) + "/" + std::to_string(tiles.size()) + " - tile " +
        tileLabel(t.row, t.col) + " (L " + neighbour(t.row, t.col - 1) + ", R " +
        neighbour(t.row, t.col + 1) + ", up " + neighbour(t.row - 1, t.col) + ", down " +
        neighbour(t.row + 1, t.col) + ") - overlap 1 cm: next tile's frame on the dashed line";
    cs << "BT /F1 7 Tf " << fixed(ox, 3) << " " << fixed(0.35 * pt, 3) << " Td " << pdfString(label)
       << " Tj ET\n";
    cs << "BT /F1 12 Tf " << fixed(ox, 3) << " " << fixed((spec.heightCm - 0.75) * pt, 3) << " Td "
       << pdfString(tileLabel(t.row, t.col)) << " Tj ET\n";
    // Clip to the frame and draw the sheet shifted so that this tile's corner is at the
    // frame's top-left corner.
    cs << "q " << fixed(ox, 3) << " " << fixed(oy, 3) << " " << fixed(tileW * pt, 3) << " "
       << fixed(tileH * pt, 3) << " re W n\n"
       << "1 0 0 1 " << fixed(ox - t.x0 * pt, 3) << " " << fixed(oyTop + t.y0 * pt, 3) << " cm\n"
       << geometry << "Q\n";
    doc.addPage(spec.widthCm, spec.heightCm, cs.str());
  }
  return doc.bytes(text.style + " " + pattern.type + " size " + text.size);
}

std::string patternPdfA4(const Pattern& pattern, const PieceText& text) {
  return patternPdf(pattern, text, Paper::kA4);
}

}  // namespace garmcap::drafts
