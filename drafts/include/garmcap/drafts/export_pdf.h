#pragma once
// Pattern PDFs for printing at 100 %: tiled office paper (A4, US Letter) or A0 plotter pages.

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class PdfExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

enum class Paper { kA4, kLetter, kA0 };

/// The page and its tiling: portrait page size, 10 mm margins around the tile (the printable
/// frame), neighbouring tiles overlap by `overlapCm`.
struct PaperSpec {
  const char* name;
  double widthCm;
  double heightCm;
  double marginCm = 1.0;
  double overlapCm = 1.0;
  double testSquareCm = 10.0;  // 4 in (10.16 cm) on US Letter
  const char* testSquareLabel = "10 cm";
};
PaperSpec paperSpec(Paper paper);
/// "a4", "letter", "a0" (case-insensitive); throws std::invalid_argument naming the choices.
Paper parsePaper(const std::string& name);

/// The pattern at exactly 1:1 (PDF 1.4, vector, uncompressed) on `paper`: the pieces (cut line
/// solid, sew line dashed, darts, notches, fold marks, grain lines with an arrowhead at each end)
/// laid out on one sheet that is cut into tiles of the paper's frame; neighbouring tiles overlap
/// by 1 cm (the dashed line 1 cm inside the right and bottom frame edge is where the next tile's
/// frame edge goes) and carry match marks (a filled dot and cross with the two tiles' labels,
/// e.g. "A1|A2", in the shared strip, drawn on both). Tiles are labelled by row letter and column
/// number; only tiles that hold part of a piece (or the test square) become pages. The first
/// page holds the test square (10 cm, 4 in on Letter) with its size printed and the seam
/// allowance statement. A0: the same with one A0 frame as the tile (a plotter's few pages).
/// Throws PdfExportError for a pattern without panels.
std::string patternPdf(const Pattern& pattern, const PieceText& text, Paper paper);
/// patternPdf(pattern, text, Paper::kA4).
std::string patternPdfA4(const Pattern& pattern, const PieceText& text);

}  // namespace garmcap::drafts
