#pragma once
// Pattern exports: drafts::Pattern in, file bytes out. Pure functions, thread-safe.
//
// Coordinates: patterns are in cm with y DOWN (drafts/pattern.h). DXF files are written in mm
// with y UP (DXF convention): x_dxf = 10 * x, y_dxf = -10 * y. SVG and PDF are 1:1 (1 cm on
// the page is 1 cm of pattern). Outlines are the panel outlines as drafted (net, without seam
// allowance); the allowance is stated in each piece's text. Formats: docs/exports.md.

#include <string>
#include <vector>

#include "garmcap/daemon/export_shop.h"
#include "garmcap/drafts/pattern.h"

namespace garmcap::daemon {

/// What is printed on each piece besides the geometry.
struct PieceText {
  std::string style;             // style name, usually the SKU
  std::string size;              // size label of this pattern, e.g. "M"
  std::string fabric = "SHELL";  // ASTM "Material"
};

/// Outline vertices that are turn points (corners, seam ends, dart legs, notches) rather than
/// curve points. Same indices for every size of a DSW-graded run (decided on `panel` alone).
std::vector<int> turnPointIndices(const drafts::Panel& panel, const drafts::Pattern& pattern);

/// SVG at 1:1 (width/height in mm, viewBox in mm): every panel outline, darts, notches,
/// grainline, internal lines and its name/size/cut text, panels side by side.
std::string patternSvg(const drafts::Pattern& pattern, const PieceText& text);

/// DXF-AAMA (ASTM D6673 conventions, DXF R12 / AC1009), one size: one BLOCK per piece named
/// "<piece>_<size>" with layer 1 boundary (closed POLYLINE) and piece text (Piece Name, Size,
/// Quantity, Material, Seam allowance), layer 2 turn points, layer 3 curve points, layer 4
/// notches (LINE from the outline inwards), layer 7 grainline, layer 8 internal lines and dart
/// legs, layer 13 drill holes at dart apexes; an INSERT of each block in ENTITIES.
std::string patternDxf(const drafts::Pattern& pattern, const PieceText& text);

/// A graded size run: the same panels (same names, same vertex count and order) per size.
struct GradedRun {
  std::string style;
  std::vector<std::string> sizes;         // smallest first
  std::string sampleSize;                 // one of `sizes`: the captured (base) size
  std::vector<drafts::Pattern> patterns;  // one per size, same order as `sizes`
};

/// Throws ExportError when sizes and patterns differ in number, the sample size is not in the
/// list, or a panel differs between sizes in name or vertex count.
void checkGradedRun(const GradedRun& run);

/// Every size of every piece in one ASTM DXF (blocks "<piece>_<size>", nested at the same
/// origin), the sample size's blocks carrying "Sample Size" text and "# N" grade-rule numbers
/// on layer 2 at their turn points, numbered as in gradeRuleTable().
std::string gradedDxf(const GradedRun& run);

/// ASTM D6673 grade-rule table (.RUL, ASCII): size list, sample size, and for every turn point
/// of every piece (numbered from 1, pieces in pattern order, turn points in outline order) a
/// rule "RULE: DELTA N" with one dx,dy pair (mm, y up) per size, the sample size's pair 0,0.
std::string gradeRuleTable(const GradedRun& run);

/// GarmentCode JSON pattern (pygarment spec: panels with vertices, edges with relative cubic
/// curvature, stitches from the pattern's seam pairs; units_in_meter 100, y up, loops
/// counter-clockwise). Draping tools can load it.
std::string garmentCodeJson(const drafts::Pattern& pattern, const PieceText& text);

/// Tiled PDF for printing on A4 portrait at 100 % (PDF 1.4, vector, uncompressed): pages in
/// rows and columns over the panel layout, 10 mm margins, tile marks and row/column labels
/// on every page, a 10 cm x 10 cm test square on the first page.
std::string patternPdfA4(const drafts::Pattern& pattern, const PieceText& text);

/// Panels laid out side by side (left to right in rows no wider than `maxRowWidthCm`), each
/// panel's outline bounding box moved to its slot: the offset to add to that panel's points.
/// Also the total sheet size in cm.
struct Layout {
  std::vector<drafts::Point2> offsets;  // one per panel
  double widthCm = 0;
  double heightCm = 0;
};
Layout layoutPanels(const drafts::Pattern& pattern, double gapCm, double maxRowWidthCm);

}  // namespace garmcap::daemon
