// `garmcap coords`, `garmcap grade`, `garmcap sizerun`: thin wiring of options to core/dsw.
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_nested_grading.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/drafts/svg.h"
#include "garmcap/dsw/coordinates.h"
#include "garmcap/dsw/grading.h"
#include "garmcap/dsw/points_io.h"
#include "garmcap/dsw/size_guide.h"
#include "garmcap/dsw/size_run.h"

namespace garmcap::cli {
namespace {

namespace gd = garmcap::drafts;
namespace dsw = garmcap::dsw;

dsw::CoordMethod method(const std::string& name) {
  auto m = dsw::parseCoordMethod(name);
  if (!m)
    throw std::invalid_argument("--coords/--method '" + name +
                                "': expected mvc, wachspress, green or tbc");
  return *m;
}

struct CoordsOptions {
  std::string method = "mvc";
  std::string polygon;
  std::string points;
};

void runCoords(const CoordsOptions& o) {
  const dsw::Points polygon = dsw::readPointsFile(o.polygon, "polygon");
  const dsw::Points points = dsw::readPointsFile(o.points, "points");
  auto enc = dsw::encodePoints(method(o.method), polygon, points);
  if (!enc)
    throw std::runtime_error("coords: " + o.polygon + ": " + enc.error().message);
  nlohmann::json out{{"weights", dsw::matrixToJson(enc->weights)}};
  if (enc->method == dsw::CoordMethod::kGreen)
    out["edge_weights"] = dsw::matrixToJson(enc->edgeWeights);
  std::cout << out.dump() << "\n";
}

struct GradeCliOptions {
  std::string pattern;
  std::string to;
  std::string size;
  std::string chart;
  std::string coords = "mvc";
  bool dartCompensation = false;
  std::optional<double> marginCm;
  bool baseDraft = false;
  std::string out;
  std::string svg;
};

dsw::GradeOptions gradeOptions(const GradeCliOptions& o) {
  dsw::GradeOptions g;
  g.method = method(o.coords);
  g.dartCompensation = o.dartCompensation;
  g.marginCm = o.marginCm;
  g.baseDraft = o.baseDraft;
  return g;
}

void runGrade(const GradeCliOptions& o) {
  const bool fromFile = !o.to.empty();
  const bool fromChart = !o.size.empty() || !o.chart.empty();
  if (fromFile == fromChart || (fromChart && (o.size.empty() || o.chart.empty())))
    throw std::invalid_argument("grade: give either --to BODY or both --size S and --chart C");
  const gd::Pattern source = gd::readPatternJson(o.pattern);
  const gd::Measurements body =
      fromFile ? gd::readMeasurementsFile(o.to) : gd::sizeChart(o.chart).body(o.size);
  auto graded = dsw::gradePattern(source, body, gradeOptions(o));
  if (!graded)
    throw std::runtime_error("grade: " + o.pattern + ": " + graded.error().message);
  gd::writePatternJson(o.out, *graded);
  if (!o.svg.empty())
    gd::writePatternSvg(o.svg, *graded);
}

void runSizeRun(const GradeCliOptions& o) {
  const gd::Pattern source = gd::readPatternJson(o.pattern);
  const gd::SizeChart& chart = gd::sizeChart(o.chart);
  auto run = dsw::gradeSizeRun(source, chart, gradeOptions(o));
  if (!run)
    throw std::runtime_error("sizerun: " + o.pattern + ": " + run.error().message);
  const std::filesystem::path dir = o.out;
  for (std::size_t i = 0; i < run->sizes.size(); ++i) {
    const std::string base = source.type + "_" + run->sizes[i];
    gd::writePatternJson(dir / (base + ".json"), run->patterns[i]);
    gd::writePatternSvg(dir / (base + ".svg"), run->patterns[i]);
  }
  // The source pattern is the item: its own measurements are the guide's row for the chart size
  // nearest to the body it was drafted for (dsw::sampleSizeOf).
  const auto nearest = dsw::sampleSizeOf(source, chart);
  if (!nearest)
    throw std::runtime_error("sizerun: " + o.pattern +
                             ": the pattern's body has no bust, waist or hip to size it by");
  const std::string type = dsw::garmentTypeOfRecipe(source.type).value_or(source.type);
  auto guide = dsw::buildSizeGuide(
      *run, chart, type, dsw::shopperMeasurements(type, gd::measurePattern(source)), *nearest);
  if (!guide)
    throw std::runtime_error("sizerun: " + o.pattern + ": " + guide.error().message);
  gd::writeFileAtomic(dir / "size_guide.json", dsw::sizeGuideJson(*guide));
  gd::writeFileAtomic(dir / "size_guide.csv", dsw::sizeGuideCsv(*guide));
  // The run for a grading CAD: every size's blocks, the item's size as the sample, its rules.
  const gd::GradedRun graded{source.type, run->sizes, chart.sizes[*nearest], run->patterns};
  gd::writeFileAtomic(dir / "graded.dxf", gd::gradedDxf(graded));
  gd::writeFileAtomic(dir / "graded.rul", gd::gradeRuleTable(graded));
  // Every size superimposed per piece, the sample size marked (nested grading).
  gd::writeFileAtomic(dir / "nested_grading.svg", gd::nestedGradingSvg(graded));
  gd::writeFileAtomic(dir / "nested_grading.pdf", gd::nestedGradingPdf(graded));
  gd::writeFileAtomic(dir / "nested_grading.dxf", gd::nestedGradingDxf(graded));
}

void addGradingOptions(CLI::App* cmd, GradeCliOptions& o) {
  cmd->add_option("--pattern", o.pattern, "Source pattern JSON (panels drawn on their draft)")
      ->required();
  cmd->add_option("--coords", o.coords, "Coordinates: mvc (default), tbc, green, wachspress");
  cmd->add_flag("--dart-compensation", o.dartCompensation,
                "Restore the source's waist margin in every size by the waist darts (eq. 4.14)");
  cmd->add_option("--margin", o.marginCm,
                  "Waist margin m of the dart compensation, cm (default: the source pattern's own "
                  "waist ease, so the base size keeps its waist; a value overrides that ease)");
  cmd->add_flag("--base-draft", o.baseDraft,
                "Grade through the base block instead of the garment's draft (4.4)");
}

}  // namespace

void addDswCommands(CLI::App& app) {
  auto co = std::make_shared<CoordsOptions>();
  CLI::App* coords = app.add_subcommand("coords",
                                        "Generalized barycentric coordinates of points in a "
                                        "polygon: prints {\"weights\": [[...], ...]}");
  coords->add_option("--method", co->method, "mvc (default), wachspress, green or tbc");
  coords->add_option("--polygon", co->polygon, "JSON {\"polygon\": [[x, y], ...]}")->required();
  coords->add_option("--points", co->points, "JSON {\"points\": [[x, y], ...]}")->required();
  coords->callback([co] { runCoords(*co); });

  auto go = std::make_shared<GradeCliOptions>();
  CLI::App* grade =
      app.add_subcommand("grade", "Grade a pattern's panels to a body by draft-space warping");
  addGradingOptions(grade, *go);
  grade->add_option("--to", go->to, "Target body: measurements JSON or Valentina .vit");
  grade->add_option("--size", go->size, "Target size of --chart");
  grade->add_option("--chart", go->chart, "Size chart (e.g. korean_women)");
  grade->add_option("--out", go->out, "Graded pattern JSON to write")->required();
  grade->add_option("--svg", go->svg, "SVG of the graded pattern (true scale)");
  grade->callback([go] { runGrade(*go); });

  auto so = std::make_shared<GradeCliOptions>();
  CLI::App* sizerun = app.add_subcommand(
      "sizerun",
      "Grade a pattern to every size of a chart: panels per size, a size guide (JSON, CSV) and "
      "the graded DXF-AAMA with its ASTM grade-rule table (graded.dxf, graded.rul), every size "
      "nested per piece (nested_grading.svg/.pdf/.dxf)");
  addGradingOptions(sizerun, *so);
  sizerun->add_option("--chart", so->chart, "Size chart (e.g. korean_women)")->required();
  sizerun->add_option("--out", so->out, "Output folder")->required();
  sizerun->callback([so] { runSizeRun(*so); });
}

}  // namespace garmcap::cli
