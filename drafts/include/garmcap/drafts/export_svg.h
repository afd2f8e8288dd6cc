#pragma once
// SVG of a pattern's pieces at 1:1 in millimetres (for cutting; svg.h draws the draft in cm).

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class SvgExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// width/height in mm and viewBox in mm (1 user unit = 1 mm): every panel outline, darts,
/// notches, grainline, internal lines and its name/size/cut text, panels side by side.
/// Throws SvgExportError for a pattern without panels.
std::string patternSvg(const Pattern& pattern, const PieceText& text);

}  // namespace garmcap::drafts
