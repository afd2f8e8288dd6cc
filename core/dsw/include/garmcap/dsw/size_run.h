#pragma once
// A size run: one source pattern graded to every size of a chart, with a size guide (the
// garment measurements of each graded pattern, drafts::measurePattern) as JSON and CSV.

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
};

/// Grades `source` to every size of `chart`; the encoding is computed once and decoded per
/// size (base-draft grading and dart compensation go through gradePattern per size). Errors
/// name the size.
Expected<SizeRun> gradeSizeRun(const drafts::Pattern& source, const drafts::SizeChart& chart,
                               const GradeOptions& options = {});

/// {"units": "cm", "type": ..., "chart": ..., "sizes": [{"size": "44", "garment": {...},
/// "body": {...}}, ...]}
std::string sizeGuideJson(const SizeRun& run, const std::string& type, const std::string& chart);
/// size,<garment keys...> one row per size, values to 0.1 mm.
std::string sizeGuideCsv(const SizeRun& run);

}  // namespace garmcap::dsw
