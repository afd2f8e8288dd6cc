// ASTM D6673 grade-rule table (.RUL): one DELTA rule per grade point (turn points and the curve
// points proportional curve grading needs), one dx,dy pair per size.
#include "garmcap/drafts/export_rul.h"

#include <sstream>

#include "export_util.h"

namespace garmcap::drafts {

using detail::asciiText;
using detail::fixed;

std::string gradeRuleTable(const GradedRun& run) {
  try {
    checkGradedRun(run);
  } catch (const PatternExportError& e) {
    throw RulExportError(e.what());
  }
  const size_t si = sampleIndex(run);
  const auto& sample = run.patterns[si];
  std::ostringstream os;
  os << kAstmVersionLine << "\r\n"
     << "AUTHOR: GarmCap Station\r\nPRODUCT: GarmCap Station\r\nVERSION: 1\r\n"
     << "UNITS: METRIC\r\n"
     << "GRADE RULE TABLE: " << asciiText(run.style) << "\r\n"
     << "NUMBER OF SIZES: " << run.sizes.size() << "\r\n"
     << "SIZE LIST:";
  for (const auto& s : run.sizes)
    os << " " << asciiText(s);
  os << "\r\nSAMPLE SIZE: " << asciiText(run.sampleSize) << "\r\n";
  int rule = 1;
  for (size_t i = 0; i < sample.panels.size(); ++i) {
    for (int v : gradePointIndices(run, i)) {
      os << "RULE: DELTA " << rule++ << "\r\n";
      const Point2 base = sample.panels[i].outline[static_cast<size_t>(v)];
      for (size_t s = 0; s < run.sizes.size(); ++s) {
        Point2 p = run.patterns[s].panels[i].outline[static_cast<size_t>(v)];
        double dx = (p.x() - base.x()) * 10.0, dy = -(p.y() - base.y()) * 10.0;
        os << (s % 5 == 0 ? "" : " ") << fixed(dx, 3) << "," << fixed(dy, 3);
        if (s % 5 == 4 || s + 1 == run.sizes.size())
          os << "\r\n";
      }
    }
  }
  os << "END\r\n";
  return os.str();
}

}  // namespace garmcap::drafts
