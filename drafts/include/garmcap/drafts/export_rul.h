#pragma once
// ASTM D6673 grade-rule table (.RUL, ASCII) of a graded run, the companion of gradedDxf().

#include <string>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class RulExportError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// Size list, sample size, and for every turn point of every piece (numbered from 1, pieces in
/// pattern order, turn points in outline order) a rule "RULE: DELTA N" with one dx,dy pair
/// (mm, y up) per size, the sample size's pair 0,0. Throws RulExportError for a run
/// checkGradedRun refuses.
std::string gradeRuleTable(const GradedRun& run);

}  // namespace garmcap::drafts
