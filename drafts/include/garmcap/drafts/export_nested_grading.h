#pragma once
// Nested grading: every size of a graded run superimposed, one drawing per piece, so that a
// pattern maker sees the grade at a glance. Reference point: every size of a piece is moved so
// that the top of its outline (smallest y) at the x of its fold (the centre front/back of a
// piece cut on the fold), or else at the middle of its width (a sleeve's cap top, a skirt
// panel's waist), lies on the sample size's; the sizes then fan out from there. Each size in
// its own colour (past eight sizes, dashed), the sample size thicker and labelled, a legend of
// the sizes. Sew lines (the net blocks the grade rules move) are drawn.

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class NestedGradingError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// SVG at 1:1 in mm (1 user unit = 1 mm). Each piece is a <g class="piece"> holding one
/// <polygon data-size="S"> per size (the sample's with data-sample="1").
std::string nestedGradingSvg(const GradedRun& run);
/// PDF: one page with every piece, 1:1, 2 cm border (a plotter page).
std::string nestedGradingPdf(const GradedRun& run);
/// DXF R12 in mm (y up): one layer "SIZE_<size>" per size holding that size's closed sew
/// lines, the sample's grain lines on "GRAIN", piece names and the legend (the sample marked
/// "(sample)") on "TEXT".
std::string nestedGradingDxf(const GradedRun& run);

}  // namespace garmcap::drafts
