#pragma once
// GarmentCode (pygarment) pattern specification JSON, for draping tools.

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class GarmentCodeExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// pattern.panels with vertices (cm, y up), edges with relative cubic curvature, stitches from
/// the pattern's seam pairs; units_in_meter 100, loops counter-clockwise. Throws
/// GarmentCodeExportError naming the panel or seam that cannot be written.
std::string garmentCodeJson(const Pattern& pattern, const PieceText& text);

}  // namespace garmcap::drafts
