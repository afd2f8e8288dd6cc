// DXF-AAMA / ASTM D6673 writer (R12 group codes): one size or a graded run in one file.
#include "garmcap/drafts/export_dxf_aama.h"

#include <map>
#include <set>

#include "dxf_r12.h"
#include "export_util.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/seam_allowance.h"

namespace garmcap::drafts {
namespace {

using detail::blockName;
using detail::Box;
using detail::fixed;
using detail::inwardNormal;
using detail::panelBox;

using Dxf = detail::DxfR12;

// The header and the layer table of a DXF-AAMA file: the AAMA/ASTM layer numbers. No LTYPE
// table: every layer is CONTINUOUS, which R12 readers know without one (ezdxf audits clean).
void dxfHeader(Dxf& d) {
  std::vector<detail::DxfLayer> layers;
  for (const char* l : {"1", "2", "3", "4", "6", "7", "8", "13", "14", "15"})
    layers.push_back({l, 7, "CONTINUOUS"});
  d.headerAndTables(layers, false);
}

// One piece of one size as a BLOCK. `ruleAt` (outline index -> rule number, empty but in the
// sample block) is written as a "# N" text on layer 2 right after its grade point: a layer-2
// turn point or a layer-3 curve point that proportional curve grading alone would misplace.
void dxfPieceBlock(Dxf& d, const Pattern& pattern, const Panel& panel, const std::string& size,
                   const PieceText& text, const std::vector<int>& turns,
                   const std::map<int, int>& ruleAt, bool sample) {
  detail::checkPanel<DxfExportError>(panel);
  const std::string name = blockName(panel.name, size);
  d.code(0, "BLOCK");
  d.code(8, "0");
  d.code(2, name);
  d.code(70, "0");
  d.code(10, "0.0");
  d.code(20, "0.0");
  d.code(30, "0.0");
  d.code(3, name);

  // Layer 1 is the cut line (allowance included), layer 14 the sew line (the net outline).
  const Polyline cut = detail::cutLine<DxfExportError>(panel, pattern);
  d.polyline("1", cut, true);
  d.polyline("14", panel.outline, true);
  if (auto fold = foldEdge(panel, pattern))  // layer 6: the mirror line of a piece cut on fold
    d.line("6", panel.outline[static_cast<size_t>(fold->from)],
           panel.outline[static_cast<size_t>(fold->to)]);

  const std::set<int> turnSet(turns.begin(), turns.end());
  auto ruleText = [&](int v, const Point2& p) {
    if (const auto r = ruleAt.find(v); r != ruleAt.end())
      d.text("2", p, 3.0, "# " + std::to_string(r->second));
  };
  for (int v : turns) {
    const auto& p = panel.outline[static_cast<size_t>(v)];
    d.point("2", p);
    ruleText(v, p);
  }
  for (size_t i = 0; i < panel.outline.size(); ++i)
    if (!turnSet.count(static_cast<int>(i))) {
      d.point("3", panel.outline[i]);
      ruleText(static_cast<int>(i), panel.outline[i]);
    }

  for (const auto& n : panel.notches) {  // 5 mm slit from the cut line
    const auto slit = detail::notchSlit(panel.outline, cut, n.position);
    d.line("4", slit.from, slit.to);
  }
  d.line("7", panel.grainline.start, panel.grainline.end);
  for (const auto& dart : panel.darts) {
    d.polyline("8", dartPath(panel, dart), false);
    d.point("13", dart.apex);
  }
  for (const auto& l : panel.internalLines)
    d.polyline("8", l.points, false);

  Box b = panelBox(panel);
  Point2 at(b.min.x() + 0.15 * b.width(), b.min.y() + 0.3 * b.height());
  std::vector<std::string> lines = {"Piece Name: " + panel.name,
                                    "Size: " + size,
                                    "Quantity: " + std::to_string(panel.cutCount),
                                    "Material: " + text.fabric,
                                    "Style Name: " + text.style,
                                    "Category: " + pattern.type};
  if (panel.cutOnFold)
    lines.push_back("Annotation: cut on fold");
  lines.push_back("Annotation: " + detail::allowanceNote(panel));
  if (sample)
    lines.push_back("Sample Size: " + size);
  for (size_t i = 0; i < lines.size(); ++i)
    d.text("1", at + Point2(0, 0.8 * static_cast<double>(i)), 5.0, lines[i]);
  d.code(0, "ENDBLK");
  d.code(8, "0");
}

void dxfStyleText(Dxf& d, const std::vector<std::string>& lines) {
  for (size_t i = 0; i < lines.size(); ++i)
    d.text("1", Point2(0, -5.0 - 0.8 * static_cast<double>(lines.size() - i)), 5.0, lines[i]);
}

void dxfInsert(Dxf& d, const std::string& name) {
  d.code(0, "INSERT");
  d.code(8, "1");
  d.code(2, name);
  d.code(10, "0.0");
  d.code(20, "0.0");
  d.code(30, "0.0");
}

}  // namespace

std::string patternDxf(const Pattern& pattern, const PieceText& text) {
  detail::checkPattern<DxfExportError>(pattern);
  Dxf d;
  dxfHeader(d);
  d.beginSection("BLOCKS");
  for (const auto& p : pattern.panels)
    dxfPieceBlock(d, pattern, p, text.size, text, turnPointIndices(p, pattern), {}, false);
  d.endSection();
  d.beginSection("ENTITIES");
  dxfStyleText(d, {kAstmVersionLine, "Style Name: " + text.style, "Units: METRIC",
                   "Size: " + text.size, "Author: GarmCap Station"});
  for (const auto& p : pattern.panels)
    dxfInsert(d, blockName(p.name, text.size));
  return d.finish();
}

std::string gradedDxf(const GradedRun& run) {
  try {
    checkGradedRun(run);
  } catch (const PatternExportError& e) {
    throw DxfExportError(e.what());
  }
  const size_t si = sampleIndex(run);
  const auto& sample = run.patterns[si];
  Dxf d;
  dxfHeader(d);
  d.beginSection("BLOCKS");
  // Rules numbered as the RUL numbers them: pieces in order, grade points ascending.
  int rule = 1;
  std::vector<std::vector<int>> turnsPerPanel;
  std::vector<std::map<int, int>> rulesPerPanel;
  for (size_t i = 0; i < sample.panels.size(); ++i) {
    turnsPerPanel.push_back(turnPointIndices(sample.panels[i], sample));
    std::map<int, int> rules;
    for (int v : gradePointIndices(run, i))
      rules[v] = rule++;
    rulesPerPanel.push_back(std::move(rules));
  }
  for (size_t s = 0; s < run.sizes.size(); ++s) {
    const PieceText text{run.style, run.sizes[s]};
    for (size_t i = 0; i < run.patterns[s].panels.size(); ++i)
      dxfPieceBlock(d, run.patterns[s], run.patterns[s].panels[i], run.sizes[s], text,
                    turnsPerPanel[i], s == si ? rulesPerPanel[i] : std::map<int, int>{}, s == si);
  }
  d.endSection();
  d.beginSection("ENTITIES");
  std::string list;
  for (const auto& s : run.sizes)
    list += (list.empty() ? "" : " ") + s;
  dxfStyleText(
      d, {kAstmVersionLine, "Style Name: " + run.style, "Units: METRIC",
          "Grade Rule Table: " + run.style, "Number of Sizes: " + std::to_string(run.sizes.size()),
          "Size List: " + list, "Sample Size: " + run.sampleSize, "Author: GarmCap Station"});
  for (size_t s = 0; s < run.sizes.size(); ++s)
    for (const auto& p : run.patterns[s].panels)
      dxfInsert(d, blockName(p.name, run.sizes[s]));
  return d.finish();
}

}  // namespace garmcap::drafts
