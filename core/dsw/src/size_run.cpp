#include "garmcap/dsw/size_run.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"

namespace garmcap::dsw {

Expected<SizeRun> gradeSizeRun(const drafts::Pattern& source, const drafts::SizeChart& chart,
                               const GradeOptions& options) {
  SizeRun run;
  bool hasRecipe = false;
  for (const auto& t : drafts::garmentTypes())
    hasRecipe = hasRecipe || t.name == source.type;
  const bool reuse =
      hasRecipe && !options.baseDraft && !options.dartCompensation && !source.regions.empty();
  std::optional<EncodedPattern> encoded;
  if (reuse) {
    auto enc = encodePattern(source, source.regions, options.method);
    if (!enc)
      return enc.error();
    encoded = std::move(enc).value();
  }
  for (std::size_t i = 0; i < chart.sizes.size(); ++i) {
    const std::string& size = chart.sizes[i];
    Expected<drafts::Pattern> graded = Error{""};
    if (encoded) {
      auto draft = targetDraft(source, chart.bodies[i]);
      if (!draft)
        return Error{"size " + size + ": " + draft.error().message};
      graded = decodePattern(*encoded, *draft);
    } else {
      graded = gradePattern(source, chart.bodies[i], options);
    }
    if (!graded)
      return Error{"size " + size + ": " + graded.error().message};
    std::map<std::string, double> garment;
    try {
      garment = drafts::measurePattern(*graded);
    } catch (const std::exception& e) {
      return Error{"size " + size + ": measuring the graded panels: " + e.what()};
    }
    run.sizes.push_back(size);
    run.patterns.push_back(std::move(graded).value());
    run.garment.push_back(std::move(garment));
    run.body.push_back(chart.bodies[i].values());
  }
  return run;
}

std::string sizeGuideJson(const SizeRun& run, const std::string& type, const std::string& chart) {
  nlohmann::json sizes = nlohmann::json::array();
  auto rounded = [](const std::map<std::string, double>& m) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& [k, v] : m)
      o[k] = std::round(v * 1000) / 1000;
    return o;
  };
  for (std::size_t i = 0; i < run.sizes.size(); ++i)
    sizes.push_back({{"size", run.sizes[i]},
                     {"garment", rounded(run.garment[i])},
                     {"body", rounded(run.body[i])}});
  return nlohmann::json{{"units", "cm"}, {"type", type}, {"chart", chart}, {"sizes", sizes}}.dump(
             2) +
         "\n";
}

std::string sizeGuideCsv(const SizeRun& run) {
  std::set<std::string> keys;
  for (const auto& g : run.garment) {
    for (const auto& [k, v] : g)
      keys.insert(k);
  }
  std::string out = "size";
  for (const auto& k : keys)
    out += "," + k;
  out += "\n";
  char buf[64];
  for (std::size_t i = 0; i < run.sizes.size(); ++i) {
    out += run.sizes[i];
    for (const auto& k : keys) {
      auto it = run.garment[i].find(k);
      if (it == run.garment[i].end()) {
        out += ",";
        continue;
      }
      std::snprintf(buf, sizeof buf, ",%.2f", it->second);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace garmcap::dsw
