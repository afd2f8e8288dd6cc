#pragma once
// SVG export of a pattern at true scale: width/height are given in cm and the viewBox is in cm,
// so printing at 100 % gives real size. Draft construction lines are grey, draft contours black,
// panels are drawn distinctly on top (light fill; the cut line with seam allowance solid black,
// the sew line dashed blue, a legend naming both) with their name, cut count, grainline
// (arrowed), notches and darts. A 10 cm scale bar is included.

#include <filesystem>
#include <string>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

struct SvgOptions {
  bool drawDraft = true;        // construction lines and contours of the draft
  bool drawPanels = true;       // panels with annotations
  bool drawPointNames = false;  // names of the draft points (busy; for debugging recipes)
  double marginCm = 3.0;        // blank border around the drawing
};

std::string patternToSvg(const Pattern& pattern, const SvgOptions& options = {});
void writePatternSvg(const std::filesystem::path& path, const Pattern& pattern,
                     const SvgOptions& options = {});

}  // namespace garmcap::drafts
