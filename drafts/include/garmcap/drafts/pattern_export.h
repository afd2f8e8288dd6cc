#pragma once
// What every pattern file writer shares (DXF-AAMA, RUL, GarmentCode, PDF, SVG: one header per
// format beside this one): the error base, the text printed on pieces, the graded run, turn
// points and the side-by-side layout. Pure functions, thread-safe.
//
// Coordinates: patterns are in cm with y DOWN (pattern.h). DXF files are written in mm with y UP
// (DXF convention): x_dxf = 10 * x, y_dxf = -10 * y. SVG and PDF are 1:1 (1 cm on the page is
// 1 cm of pattern). Formats and the readers they were checked with: docs/exports.md.

#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

/// A pattern that cannot be written (no panels, a degenerate outline, a seam that names a
/// missing panel, sizes that do not correspond). Each format derives its own type from it, so
/// a caller can tell which writer refused; the message names the panel or size.
class PatternExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The standard the pattern files follow, as AccuMark's own ASTM exports name it: the first line
/// of the .RUL and a style text of the DXF. The DXF itself is R12 (AC1009), as in AccuMark's
/// D6673-04 files and ezdxf's Gerber D6673 exporter (docs/exports.md, "DXF version").
inline constexpr const char* kAstmVersionLine = "ASTM/D13Proposal 1 Version: D 6673-04";

/// The name a person reads on a piece ("Bodice front", "Skirt back", "Sleeve", "Trousers
/// front") for the panel id (`bodice_front`, ...), which stays the key in file structure (SVG
/// ids, DXF block and AAMA piece names, RUL, GarmentCode). An unknown id reads as itself with
/// spaces for underscores and a capital first letter.
std::string pieceTitle(const std::string& panelName);

/// What is printed on each piece besides the geometry.
struct PieceText {
  std::string style;             // style name, usually the SKU
  std::string size;              // size label of this pattern, e.g. "M"
  std::string fabric = "SHELL";  // ASTM "Material"
};

/// Outline vertices that are turn points (corners, seam ends, dart legs, notches) rather than
/// curve points. Same indices for every size of a DSW-graded run (decided on `panel` alone).
/// Throws PatternExportError for an outline with fewer than 3 points or non-finite ones.
std::vector<int> turnPointIndices(const Panel& panel, const Pattern& pattern);

/// A graded size run: the same panels (same names, same vertex count and order) per size.
struct GradedRun {
  std::string style;
  std::vector<std::string> sizes;  // smallest first
  std::string sampleSize;          // one of `sizes`: the captured (base) size
  std::vector<Pattern> patterns;   // one per size, same order as `sizes`
};

/// Throws PatternExportError when sizes and patterns differ in number, the sample size is not
/// in the list, or a panel differs between sizes in name or vertex count.
void checkGradedRun(const GradedRun& run);
/// Index of the sample size in run.sizes (call checkGradedRun first).
size_t sampleIndex(const GradedRun& run);

/// How closely a grading CAD must rebuild every size from the sample and the grade rules.
constexpr double kGradeRebuildToleranceCm = 0.05;

/// The grade points of panel `panelIndex` of a checked run (outline indices, ascending): the
/// sample's turn points, plus the curve points a grading CAD needs to rebuild every size from
/// the sample and the rules within `toleranceCm`. Between two grade points such a CAD moves each
/// curve point by the two points' deltas weighted by its arc-length position on the sample
/// (proportional curve grading); where that misses a size's point by more than the tolerance,
/// the worst point becomes a grade point too, recursively (as Douglas-Peucker splits a curve).
std::vector<int> gradePointIndices(const GradedRun& run, size_t panelIndex,
                                   double toleranceCm = kGradeRebuildToleranceCm);

/// Panels laid out side by side (left to right in rows no wider than `maxRowWidthCm`), each
/// panel's outline bounding box moved to its slot: the offset to add to that panel's points.
/// Also the total sheet size in cm.
struct Layout {
  std::vector<Point2> offsets;  // one per panel
  double widthCm = 0;
  double heightCm = 0;
};
Layout layoutPanels(const Pattern& pattern, double gapCm, double maxRowWidthCm);

}  // namespace garmcap::drafts
