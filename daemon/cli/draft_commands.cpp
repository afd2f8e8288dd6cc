// `garmcap draft` and `garmcap measure`: thin wiring of options to the drafts library.
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/drafts/svg.h"

namespace garmcap::cli {
namespace {

namespace gd = garmcap::drafts;

struct DraftOptions {
  bool list = false;
  bool charts = false;
  std::string type;
  std::string measurementsFile;
  std::string size;
  std::string chart;
  std::vector<std::string> set;
  std::string out;
  std::string svg;
  bool pointNames = false;
  std::string dxf;         // DXF-AAMA pattern file (cut line with allowance, sew line)
  std::string patternPdf;  // tiled PDF on --paper
  std::string paper = "a4";
  std::string patternSvg;  // pattern pieces at 1:1 with cut and sew lines
  std::string style = "DRAFT";
  std::string vst;  // Valentina multisize table of --chart
};

std::map<std::string, double> parseSet(const std::vector<std::string>& items) {
  std::map<std::string, double> design;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw std::invalid_argument("--set '" + item + "': expected name=value");
    }
    const std::string name = item.substr(0, eq), value = item.substr(eq + 1);
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size() || value.empty()) {
      throw std::invalid_argument("--set '" + item + "': value '" + value + "' is not a number");
    }
    design[name] = v;
  }
  return design;
}

void runDraft(const DraftOptions& o) {
  if (o.list) {
    nlohmann::json types = nlohmann::json::array();
    for (const auto& t : gd::garmentTypes()) {
      nlohmann::json design = nlohmann::json::array();
      for (const auto& d : t.design) {
        nlohmann::json p = {{"name", d.name},
                            {"default", d.defaultValue},
                            {"min", d.minValue},
                            {"max", d.maxValue},
                            {"description", d.description}};
        if (!d.gradesWith.empty())
          p["grades_with"] = d.gradesWith;
        if (d.gradesFrom > 0)
          p["default_for"] = {{d.gradesWith, d.gradesFrom}};
        design.push_back(std::move(p));
      }
      types.push_back({{"name", t.name},
                       {"description", t.description},
                       {"measurements", t.measurements},
                       {"design", design}});
    }
    std::cout << nlohmann::json{{"types", types}}.dump(2) << "\n";
    return;
  }
  if (o.charts) {
    nlohmann::json charts = nlohmann::json::array();
    for (const auto& c : gd::sizeCharts()) {
      charts.push_back({{"name", c.name}, {"sizes", c.sizes}, {"source", c.source}});
    }
    std::cout << nlohmann::json{{"charts", charts}}.dump(2) << "\n";
    return;
  }
  if (!o.vst.empty()) {
    if (o.chart.empty())
      throw std::invalid_argument("draft: --vst needs --chart C (the chart it tabulates)");
    gd::writeFileAtomic(o.vst, gd::chartToVst(gd::sizeChart(o.chart)));
    if (o.type.empty())
      return;
  }
  if (o.type.empty())
    throw std::invalid_argument("draft: --type is required (see --list)");
  if (o.out.empty())
    throw std::invalid_argument("draft: --out is required");
  const bool fromFile = !o.measurementsFile.empty();
  const bool fromChart = !o.size.empty() || !o.chart.empty();
  if (fromFile == fromChart || (fromChart && (o.size.empty() || o.chart.empty()))) {
    throw std::invalid_argument(
        "draft: give either --measurements FILE or both --size S and --chart C");
  }
  const gd::Measurements body =
      fromFile ? gd::readMeasurementsFile(o.measurementsFile) : gd::sizeChart(o.chart).body(o.size);
  const gd::Pattern pattern = gd::draftGarment(o.type, body, parseSet(o.set));
  gd::writePatternJson(o.out, pattern);
  if (!o.svg.empty()) {
    gd::SvgOptions svg;
    svg.drawPointNames = o.pointNames;
    gd::writePatternSvg(o.svg, pattern, svg);
  }
  const gd::PieceText text{o.style, o.size.empty() ? "base" : o.size};
  if (!o.dxf.empty())
    gd::writeFileAtomic(o.dxf, gd::patternDxf(pattern, text));
  if (!o.patternPdf.empty())
    gd::writeFileAtomic(o.patternPdf, gd::patternPdf(pattern, text, gd::parsePaper(o.paper)));
  if (!o.patternSvg.empty())
    gd::writeFileAtomic(o.patternSvg, gd::patternSvg(pattern, text));
}

}  // namespace

void addDraftCommands(CLI::App& app) {
  auto opts = std::make_shared<DraftOptions>();
  CLI::App* draft = app.add_subcommand(
      "draft", "Draft a garment type for a body: writes the pattern JSON (and an SVG at 1:1)");
  draft->add_flag("--list", opts->list,
                  "Print the garment types with their measurements and design parameters (JSON)");
  draft->add_flag("--charts", opts->charts, "Print the built-in size charts and sizes (JSON)");
  draft->add_option("--type", opts->type, "Garment type (bodice, dress, skirt_h, ...)");
  draft->add_option("--measurements", opts->measurementsFile,
                    "Body measurements: measurements JSON or Valentina .vit");
  draft->add_option("--size", opts->size, "Size of --chart (e.g. 55)");
  draft->add_option("--chart", opts->chart, "Size chart (e.g. korean_women)");
  draft->add_option("--set", opts->set, "Design parameter name=value (repeatable)");
  draft->add_option("--out", opts->out, "Pattern JSON to write");
  draft->add_option("--svg", opts->svg, "SVG to write (true scale, cm)");
  draft->add_flag("--point-names", opts->pointNames, "Label the draft points in the SVG");
  draft->add_option("--dxf", opts->dxf,
                    "DXF-AAMA pattern file to write (layer 1 cut line, layer 14 sew line)");
  draft->add_option("--pattern-pdf", opts->patternPdf,
                    "Tiled pattern PDF to write (1:1, 1 cm overlap, match marks)");
  draft->add_option("--paper", opts->paper, "Paper of --pattern-pdf: a4 (default), letter, a0");
  draft->add_option("--pattern-svg", opts->patternSvg,
                    "Pattern pieces SVG to write (1:1 mm, cut and sew lines)");
  draft->add_option("--vst", opts->vst,
                    "Valentina multisize measurements (.vst) of --chart to write: every size, "
                    "no --type needed");
  draft->add_option("--style", opts->style, "Style name printed on the pieces (default DRAFT)");
  draft->callback([opts] { runDraft(*opts); });

  auto pattern = std::make_shared<std::string>();
  CLI::App* measure = app.add_subcommand(
      "measure", "Measure a pattern's panels (garment values in cm, table 4.3 style): JSON");
  measure->add_option("--pattern", *pattern, "Pattern JSON")->required();
  measure->callback([pattern] {
    const gd::Pattern p = gd::readPatternJson(*pattern);
    nlohmann::json m = nlohmann::json::object();
    for (const auto& [k, v] : gd::measurePattern(p))
      m[k] = std::round(v * 1000) / 1000;
    std::cout << nlohmann::json{{"type", p.type}, {"units", "cm"}, {"measurements", m}}.dump(2)
              << "\n";
  });
}

}  // namespace garmcap::cli
