#pragma once
// A size run: one source pattern graded to every size of a chart, with the garment measurements
// of each graded pattern (drafts::measurePattern). The shopper's size guide is built from a run
// by size_guide.h.

#include <map>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/grading.h"

namespace garmcap::dsw {

struct SizeRun {
  std::vector<std::string> sizes;
  std::vector<drafts::Pattern> patterns;               // one per size
  std::vector<std::map<std::string, double>> garment;  // measurePattern per size
  std::vector<std::map<std::string, double>> body;     // the chart's body per size
  std::vector<std::string> skipped;  // with SizeRunPolicy::skipUngradable: why a size is missing
};

enum class SizeRunPolicy {
  allOrNothing,    // a size that cannot be graded fails the run
  skipUngradable,  // such a size is left out and its reason kept in SizeRun::skipped
};

/// Grades `source` to every size of `chart`; the encoding is computed once and decoded per
/// size (base-draft grading and dart compensation go through gradePattern per size). Errors
/// name the size; with skipUngradable the run errs only when no size could be graded.
Expected<SizeRun> gradeSizeRun(const drafts::Pattern& source, const drafts::SizeChart& chart,
                               const GradeOptions& options = {},
                               SizeRunPolicy policy = SizeRunPolicy::allOrNothing);

}  // namespace garmcap::dsw
