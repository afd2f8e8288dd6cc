// Tiled PDF writer (PDF 1.4, uncompressed vector content, base-14 Helvetica).
#include "garmcap/drafts/export_pdf.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "export_util.h"

namespace garmcap::drafts {
namespace {

using detail::asciiText;
using detail::blockName;
using detail::Box;
using detail::fixed;
using detail::inwardNormal;
using detail::panelBox;

// ---------------------------------------------------------------------------------------------
// PDF helpers
std::string pdfString(const std::string& s) {
  std::string out = "(";
  for (unsigned char c : s) {
    if (c == '(' || c == ')' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      out += '?';  // base-14 fonts have no UTF-8; piece names are ASCII anyway
    }
  }
  return out + ")";
}

}  // namespace

std::string patternPdfA4(const Pattern& pattern, const PieceText& text) {
  detail::checkPattern<PdfExportError>(pattern);
  constexpr double kPt = 72.0 / 2.54;  // points per cm
  constexpr double kPageW = 21.0, kPageH = 29.7, kMargin = 1.0;
  constexpr double kTileW = kPageW - 2 * kMargin, kTileH = kPageH - 2 * kMargin;
  const detail::CutSheet sheet = detail::cutSheet<PdfExportError>(pattern, 2.0, 120.0);
  const Layout& lay = sheet.layout;
  // Room for the 10 cm test square above the panels on the first tile.
  const double shiftY = 13.0;
  const int cols = std::max(1, static_cast<int>(std::ceil(lay.widthCm / kTileW)));
  const int rows = std::max(1, static_cast<int>(std::ceil((lay.heightCm + shiftY) / kTileH)));

  std::vector<std::string> objects;  // object bodies, numbered from 1
  auto add = [&](std::string body) {
    objects.push_back(std::move(body));
    return static_cast<int>(objects.size());
  };
  const int catalogId = add("");  // filled later
  const int pagesId = add("");
  const int fontId = add("<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>");
  std::vector<int> pageIds;

  // Geometry in sheet cm (y down) drawn once per page; the page's transform maps the tile.
  std::ostringstream geo;
  auto P = [&](const Point2& p) { return fixed(p.x() * kPt, 3) + " " + fixed(-p.y() * kPt, 3); };
  geo << "0 0 0 RG 0.8 w 1 J 1 j\n";
  // Test square 10 x 10 cm at (2, 2) cm of the sheet.
  geo << P({2, 2}) << " m " << P({12, 2}) << " l " << P({12, 12}) << " l " << P({2, 12})
      << " l h S\n";
  geo << "BT /F1 12 Tf " << P({2.5, 7.2}) << " Td " << pdfString("10 cm test square") << " Tj ET\n";
  geo << "BT /F1 10 Tf " << P({2.5, 8.0}) << " Td " << pdfString("print at 100% / actual size")
      << " Tj ET\n";
  // What the lines are: cut on the solid line, sew on the dashed one.
  geo << "BT /F1 9 Tf " << P({2.0, 12.8}) << " Td "
      << pdfString("Cut on the solid line: " + detail::allowanceNote(pattern.panels.front()) + ".")
      << " Tj ET\n";
  geo << "BT /F1 9 Tf " << P({2.0, 13.4}) << " Td "
      << pdfString("Sew on the dashed line (the net seam line).") << " Tj ET\n";
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    const auto& p = pattern.panels[i];
    const Point2 off = lay.offsets[i] + Point2(0, shiftY);
    const Polyline& cutLine = sheet.cuts[i];
    geo << "1.2 w\n";
    for (size_t k = 0; k < cutLine.size(); ++k)
      geo << P(cutLine[k] + off) << (k ? " l\n" : " m\n");
    geo << "h S\n0.6 w [6 3] 0 d\n";
    for (size_t k = 0; k < p.outline.size(); ++k)
      geo << P(p.outline[k] + off) << (k ? " l\n" : " m\n");
    geo << "h S\n[] 0 d\n";
    if (const auto fold = detail::foldMark(p, pattern)) {
      geo << "0.8 w\n";
      for (const Polyline* pl : {&fold->bracket, &fold->arrows[0], &fold->arrows[1]})
        for (size_t k = 0; k < pl->size(); ++k)
          geo << P((*pl)[k] + off) << (k ? " l" : " m") << (k + 1 == pl->size() ? " S\n" : "\n");
      // Text along the fold: PDF angles turn counter-clockwise with y up, ours with y down.
      const double rad = -fold->labelAngleDeg * 3.14159265358979323846 / 180.0;
      const Point2 at = fold->label + off;
      geo << "BT /F1 10 Tf " << fixed(std::cos(rad), 6) << " " << fixed(std::sin(rad), 6) << " "
          << fixed(-std::sin(rad), 6) << " " << fixed(std::cos(rad), 6) << " " << P(at) << " Tm "
          << pdfString("PLACE ON FOLD") << " Tj ET\n";
    }
    geo << "0.6 w [3 2] 0 d\n";
    for (const auto& d : p.darts)
      geo << P(d.leg1 + off) << " m " << P(d.apex + off) << " l " << P(d.leg2 + off) << " l S\n";
    for (const auto& l : p.internalLines)
      for (size_t k = 0; k < l.points.size(); ++k)
        geo << P(l.points[k] + off) << (k ? " l" : " m")
            << (k + 1 == l.points.size() ? " S\n" : "\n");
    geo << "[] 0 d 0.8 w\n";
    for (const auto& n : p.notches) {
      const auto slit = detail::notchSlit(p.outline, cutLine, n.position);
      geo << P(slit.from + off) << " m " << P(slit.to + off) << " l S\n";
    }
    geo << P(p.grainline.start + off) << " m " << P(p.grainline.end + off) << " l S\n";
    Box bx = panelBox(p);
    Point2 c = (bx.min + bx.max) / 2 + off;
    geo << "BT /F1 14 Tf " << P(c + Point2(-3, 0)) << " Td " << pdfString(p.name) << " Tj ET\n";
    geo << "BT /F1 10 Tf " << P(c + Point2(-3, 0.7)) << " Td "
        << pdfString(text.style + "  size " + text.size + "  cut " + std::to_string(p.cutCount) +
                     (p.cutOnFold ? " on fold" : ""))
        << " Tj ET\n";
    geo << "BT /F1 8 Tf " << P(c + Point2(-3, 1.3)) << " Td " << pdfString(detail::allowanceNote(p))
        << " Tj ET\n";
  }
  const std::string geometry = geo.str();

  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      std::ostringstream cs;
      const double ox = kMargin * kPt, oyTop = (kPageH - kMargin) * kPt;
      // Tile frame and corner marks (outside the tile), page label.
      cs << "q 0.5 G 0.3 w " << fixed(ox, 3) << " " << fixed(kMargin * kPt, 3) << " "
         << fixed(kTileW * kPt, 3) << " " << fixed(kTileH * kPt, 3) << " re S Q\n";
      const double L = 0.6 * kPt;
      for (auto [cx, cy] :
           {std::pair{ox, kMargin * kPt}, std::pair{ox + kTileW * kPt, kMargin * kPt},
            std::pair{ox, oyTop}, std::pair{ox + kTileW * kPt, oyTop}}) {
        cs << "0 G 0.5 w " << fixed(cx - L, 3) << " " << fixed(cy, 3) << " m " << fixed(cx + L, 3)
           << " " << fixed(cy, 3) << " l S " << fixed(cx, 3) << " " << fixed(cy - L, 3) << " m "
           << fixed(cx, 3) << " " << fixed(cy + L, 3) << " l S\n";
      }
      char label[160];
      std::snprintf(
          label, sizeof label, "%s size %s - page row %d col %d of %dx%d - glue edges on frame",
          asciiText(text.style).c_str(), asciiText(text.size).c_str(), r + 1, c + 1, rows, cols);
      cs << "BT /F1 8 Tf " << fixed(ox, 3) << " " << fixed(0.35 * kPt, 3) << " Td "
         << pdfString(label) << " Tj ET\n";
      char big[32];
      std::snprintf(big, sizeof big, "%c%d", 'A' + (r % 26), c + 1);
      cs << "BT /F1 10 Tf " << fixed(ox, 3) << " " << fixed((kPageH - 0.7) * kPt, 3) << " Td "
         << pdfString(big) << " Tj ET\n";
      // Clip to the tile and draw the sheet shifted so that this tile's corner is at the
      // tile frame's top-left corner.
      cs << "q " << fixed(ox, 3) << " " << fixed(kMargin * kPt, 3) << " " << fixed(kTileW * kPt, 3)
         << " " << fixed(kTileH * kPt, 3) << " re W n\n"
         << "1 0 0 1 " << fixed(ox - c * kTileW * kPt, 3) << " "
         << fixed(oyTop + r * kTileH * kPt, 3) << " cm\n"
         << geometry << "Q\n";
      const std::string content = cs.str();
      int contentId = add("<< /Length " + std::to_string(content.size()) + " >>\nstream\n" +
                          content + "endstream");
      int pageId = add(
          "<< /Type /Page /Parent " + std::to_string(pagesId) + " 0 R /MediaBox [0 0 " +
          fixed(kPageW * kPt, 3) + " " + fixed(kPageH * kPt, 3) + "] /Resources << /Font << /F1 " +
          std::to_string(fontId) + " 0 R >> >> /Contents " + std::to_string(contentId) + " 0 R >>");
      pageIds.push_back(pageId);
    }
  }
  std::string kids;
  for (int id : pageIds)
    kids += std::to_string(id) + " 0 R ";
  objects[static_cast<size_t>(catalogId - 1)] =
      "<< /Type /Catalog /Pages " + std::to_string(pagesId) + " 0 R >>";
  objects[static_cast<size_t>(pagesId - 1)] =
      "<< /Type /Pages /Kids [" + kids + "] /Count " + std::to_string(pageIds.size()) + " >>";
  std::string out = "%PDF-1.4\n%\xE2\xE3\xCF\xD3\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < objects.size(); ++i) {
    offsets.push_back(out.size());
    out += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = out.size();
  out += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (size_t off : offsets) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%010zu 00000 n \n", off);
    out += buf;
  }
  out += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root " +
         std::to_string(catalogId) + " 0 R /Info << /Title " +
         pdfString(text.style + " " + pattern.type + " size " + text.size) +
         " /Producer (GarmCap Station) >> >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return out;
}

}  // namespace garmcap::drafts
