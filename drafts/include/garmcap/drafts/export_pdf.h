#pragma once
// Tiled PDF of a pattern for printing at 100 % on office paper.

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class PdfExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// A4 portrait (PDF 1.4, vector, uncompressed): pages in rows and columns over the panel
/// layout, 10 mm margins, tile marks and row/column labels on every page, a 10 cm x 10 cm test
/// square on the first page. Throws PdfExportError for a pattern without panels.
std::string patternPdfA4(const Pattern& pattern, const PieceText& text);

}  // namespace garmcap::drafts
