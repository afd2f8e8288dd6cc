#pragma once
// DXF-AAMA / ASTM D6673 pattern files: one size, or every size of a graded run in one file.
// Coordinates in mm, y up (pattern_export.h). Layers and texts: docs/exports.md.

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class DxfExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// One size (DXF R12 / AC1009): one BLOCK per piece named "<piece>_<size>" with layer 1
/// boundary (closed POLYLINE) and piece text (Piece Name, Size, Quantity, Material, seam
/// allowance), layer 2 turn points, layer 3 curve points, layer 4 notches, layer 7 grainline,
/// layer 8 internal lines and dart legs, layer 13 drill holes at dart apexes; an INSERT of each
/// block in ENTITIES. Throws DxfExportError for a pattern without panels or a degenerate one.
std::string patternDxf(const Pattern& pattern, const PieceText& text);

/// Every size of every piece in one file (blocks "<piece>_<size>", nested at the same origin),
/// the sample size's blocks carrying "Sample Size" text and "# N" grade-rule numbers on layer 2
/// at their turn points, numbered as in gradeRuleTable(). Throws DxfExportError for a run
/// checkGradedRun refuses.
std::string gradedDxf(const GradedRun& run);

}  // namespace garmcap::drafts
