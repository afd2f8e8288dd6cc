// Turn points, graded-run checks and the layout shared by the pattern file writers.
#include "garmcap/drafts/pattern_export.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "export_util.h"
#include "garmcap/drafts/geometry_lines.h"

namespace garmcap::drafts {

std::string pieceTitle(const std::string& panelName) {
  // Names pattern makers use where the id's words would read oddly (a sweater's body pieces,
  // trousers drafted as "pants").
  static const std::vector<std::pair<std::string, std::string>> kTitles = {
      {"body_front", "Front"},
      {"body_back", "Back"},
      {"pants_front", "Trousers front"},
      {"pants_back", "Trousers back"}};
  for (const auto& [id, title] : kTitles)
    if (id == panelName)
      return title;
  std::string title = panelName;
  std::replace(title.begin(), title.end(), '_', ' ');
  if (!title.empty() && title[0] >= 'a' && title[0] <= 'z')
    title[0] = static_cast<char>(title[0] - 'a' + 'A');
  return title;
}

namespace {
constexpr double kTurnAngleDeg = 20.0;  // a sharper bend than this is a corner, not a curve
}  // namespace

std::vector<int> turnPointIndices(const Panel& panel, const Pattern& pattern) {
  detail::checkPanel<PatternExportError>(panel);
  const auto& o = panel.outline;
  const size_t n = o.size();
  std::set<int> turns;
  for (size_t i = 0; i < n; ++i) {
    Point2 a = o[i] - o[(i + n - 1) % n];
    Point2 b = o[(i + 1) % n] - o[i];
    if (a.norm() == 0 || b.norm() == 0)
      continue;
    double cosA = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
    if (std::acos(cosA) * 180.0 / kPi > kTurnAngleDeg)
      turns.insert(static_cast<int>(i));
  }
  for (const auto& s : pattern.seams) {
    for (const auto* e : {&s.a, &s.b}) {
      if (e->panel != panel.name)
        continue;
      if (e->from >= 0 && static_cast<size_t>(e->from) < n)
        turns.insert(e->from);
      if (e->to >= 0 && static_cast<size_t>(e->to) < n)
        turns.insert(e->to);
    }
  }
  for (const auto& d : panel.darts)
    for (const auto& leg : {d.leg1, d.leg2}) {
      int v = detail::nearestVertex(o, leg);
      if (v >= 0)
        turns.insert(v);
    }
  for (const auto& nt : panel.notches) {
    int v = detail::nearestVertex(o, nt.position);
    if (v >= 0)
      turns.insert(v);
  }
  if (turns.empty())
    turns.insert(0);
  return {turns.begin(), turns.end()};
}

void checkGradedRun(const GradedRun& run) {
  if (run.sizes.empty())
    throw PatternExportError("graded run '" + run.style + "': no sizes");
  if (run.sizes.size() != run.patterns.size())
    throw PatternExportError("graded run '" + run.style + "': " + std::to_string(run.sizes.size()) +
                             " sizes but " + std::to_string(run.patterns.size()) + " patterns");
  if (std::find(run.sizes.begin(), run.sizes.end(), run.sampleSize) == run.sizes.end())
    throw PatternExportError("graded run '" + run.style + "': sample size '" + run.sampleSize +
                             "' is not in the size list");
  const auto& base = run.patterns.front();
  for (size_t s = 0; s < run.patterns.size(); ++s) {
    const auto& p = run.patterns[s];
    if (p.panels.size() != base.panels.size())
      throw PatternExportError("graded run '" + run.style + "': size " + run.sizes[s] + " has " +
                               std::to_string(p.panels.size()) + " panels, size " + run.sizes[0] +
                               " has " + std::to_string(base.panels.size()));
    for (size_t i = 0; i < p.panels.size(); ++i) {
      detail::checkPanel<PatternExportError>(p.panels[i]);
      if (p.panels[i].name != base.panels[i].name ||
          p.panels[i].outline.size() != base.panels[i].outline.size())
        throw PatternExportError("graded run '" + run.style + "': panel '" + p.panels[i].name +
                                 "' of size " + run.sizes[s] +
                                 " does not correspond vertex by vertex to size " + run.sizes[0]);
    }
  }
}

size_t sampleIndex(const GradedRun& run) {
  return static_cast<size_t>(std::find(run.sizes.begin(), run.sizes.end(), run.sampleSize) -
                             run.sizes.begin());
}

namespace {

// Splits the sample's outline span from grade point `from` forward to `to` (cyclic) at its worst
// rebuilt point while that misses a size by more than `tol`.
void splitSpan(const GradedRun& run, size_t panelIndex, size_t sample, size_t from, size_t to,
               double tol, std::set<int>& grade) {
  const Polyline& o = run.patterns[sample].panels[panelIndex].outline;
  const size_t n = o.size();
  const size_t len = (to + n - from) % n == 0 ? n : (to + n - from) % n;  // edges in the span
  if (len < 2)
    return;
  std::vector<double> arc(len + 1, 0.0);
  for (size_t k = 1; k <= len; ++k)
    arc[k] = arc[k - 1] + (o[(from + k) % n] - o[(from + k - 1) % n]).norm();
  if (arc[len] <= 0)
    return;
  double worst = tol;
  size_t worstK = 0;
  for (size_t s = 0; s < run.patterns.size(); ++s) {
    const Polyline& q = run.patterns[s].panels[panelIndex].outline;
    const Point2 dFrom = q[from] - o[from], dTo = q[to % n] - o[to % n];
    for (size_t k = 1; k < len; ++k) {
      const double t = arc[k] / arc[len];
      const size_t v = (from + k) % n;
      const double miss = (o[v] + (1 - t) * dFrom + t * dTo - q[v]).norm();
      if (miss > worst) {
        worst = miss;
        worstK = k;
      }
    }
  }
  if (worstK == 0)
    return;
  const size_t mid = (from + worstK) % n;
  grade.insert(static_cast<int>(mid));
  splitSpan(run, panelIndex, sample, from, mid, tol, grade);
  splitSpan(run, panelIndex, sample, mid, to, tol, grade);
}

}  // namespace

std::vector<int> gradePointIndices(const GradedRun& run, size_t panelIndex, double toleranceCm) {
  const size_t si = sampleIndex(run);
  const Pattern& sample = run.patterns[si];
  const std::vector<int> turns = turnPointIndices(sample.panels[panelIndex], sample);
  std::set<int> grade(turns.begin(), turns.end());
  for (size_t k = 0; k < turns.size(); ++k)
    splitSpan(run, panelIndex, si, static_cast<size_t>(turns[k]),
              static_cast<size_t>(turns[(k + 1) % turns.size()]), toleranceCm, grade);
  return {grade.begin(), grade.end()};
}

Layout layoutPanels(const Pattern& pattern, double gapCm, double maxRowWidthCm) {
  Layout lay;
  double x = gapCm, y = gapCm, rowH = 0;
  for (const auto& p : pattern.panels) {
    detail::checkPanel<PatternExportError>(p);
    const detail::Box b = detail::panelBox(p);
    if (x > gapCm && x + b.width() + gapCm > maxRowWidthCm) {
      x = gapCm;
      y += rowH + gapCm;
      rowH = 0;
    }
    lay.offsets.push_back(Point2(x, y) - b.min);
    x += b.width() + gapCm;
    rowH = std::max(rowH, b.height());
    lay.widthCm = std::max(lay.widthCm, x);
  }
  lay.heightCm = y + rowH + gapCm;
  return lay;
}

}  // namespace garmcap::drafts
