// `garmcap marker`: thin wiring of options to drafts::layMarker and the marker writers.
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/marker.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::cli {
namespace {

namespace gd = garmcap::drafts;

struct MarkerOptions {
  std::vector<std::string> patterns;
  std::vector<std::string> labels;
  std::string type;
  std::string chart;
  std::vector<std::string> sizes;
  double widthCm = 150.0;
  double gapCm = 0.2;
  int maxPieces = gd::kDefaultMarkerMaxPieces;
  std::string svg, pdf, dxf;
  std::string title;
};

void runMarker(const MarkerOptions& o) {
  std::vector<gd::SizedPattern> sized;
  if (!o.patterns.empty()) {
    if (!o.type.empty() || !o.chart.empty())
      throw std::invalid_argument("marker: give either --pattern FILE... or --type with --chart");
    if (!o.labels.empty() && o.labels.size() != o.patterns.size())
      throw std::invalid_argument("marker: give one --label per --pattern (or none)");
    for (size_t i = 0; i < o.patterns.size(); ++i)
      sized.push_back(
          {o.labels.empty() ? std::filesystem::path(o.patterns[i]).stem().string() : o.labels[i],
           gd::readPatternJson(o.patterns[i])});
  } else {
    if (o.type.empty() || o.chart.empty() || o.sizes.empty())
      throw std::invalid_argument(
          "marker: give --pattern FILE... or --type T --chart C --size S (repeatable)");
    const gd::SizeChart& chart = gd::sizeChart(o.chart);
    for (const auto& s : o.sizes)
      sized.push_back({s, gd::draftGarment(o.type, chart.body(s))});
  }
  const gd::Marker m = gd::layMarker(sized, {o.widthCm, o.gapCm, o.maxPieces});
  std::string title = o.title;
  if (title.empty()) {
    title = sized.front().pattern.type + " size";
    for (const auto& s : sized)
      title += " " + s.size;
  }
  if (!o.svg.empty())
    gd::writeFileAtomic(o.svg, gd::markerSvg(m, title));
  if (!o.pdf.empty())
    gd::writeFileAtomic(o.pdf, gd::markerPdf(m, title));
  if (!o.dxf.empty())
    gd::writeFileAtomic(o.dxf, gd::markerDxf(m));
  std::cout << gd::markerSummaryJson(m, title).dump(2) << "\n";
}

}  // namespace

void addMarkerCommands(CLI::App& app) {
  auto o = std::make_shared<MarkerOptions>();
  CLI::App* cmd = app.add_subcommand(
      "marker",
      "Lay every piece of a size (or of several sizes) on a fabric width with libnest2d, grain "
      "along the length (cut 2 = a piece and its mirror, fold pieces opened out); prints the "
      "length and efficiency (JSON) and writes SVG, PDF, DXF");
  cmd->add_option("--pattern", o->patterns, "Pattern JSON of one size (repeatable)");
  cmd->add_option("--label", o->labels, "Size label of each --pattern (default: file name)");
  cmd->add_option("--type", o->type, "Garment type to draft from --chart instead of --pattern");
  cmd->add_option("--chart", o->chart, "Size chart (e.g. korean_women)");
  cmd->add_option("--size", o->sizes, "Size of --chart (repeatable)");
  cmd->add_option("--width", o->widthCm, "Usable fabric width in cm (default 150)");
  cmd->add_option("--gap", o->gapCm, "Least distance between pieces in cm (default 0.2)");
  cmd->add_option("--max-pieces", o->maxPieces,
                  "Most pieces to lay, cut counts and sizes included (default " +
                      std::to_string(gd::kDefaultMarkerMaxPieces) +
                      "); more is refused before nesting")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--svg", o->svg, "Marker SVG to write (1:1 mm)");
  cmd->add_option("--pdf", o->pdf, "Marker PDF to write (one page, 1:1)");
  cmd->add_option("--dxf", o->dxf, "Marker DXF to write (R12, mm, one layer per size)");
  cmd->add_option("--title", o->title, "Title printed on the marker");
  cmd->callback([o] { runMarker(*o); });
}

}  // namespace garmcap::cli
