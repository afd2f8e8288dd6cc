#include "garmcap/dsw/size_run.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"

namespace garmcap::dsw {

Expected<SizeRun> gradeSizeRun(const drafts::Pattern& source, const drafts::SizeChart& chart,
                               const GradeOptions& options, SizeRunPolicy policy) {
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
    std::optional<std::string> failure;
    std::map<std::string, double> garment;
    if (!graded) {
      failure = "size " + size + ": " + graded.error().message;
    } else {
      try {
        garment = drafts::measurePattern(*graded);
      } catch (const std::exception& e) {
        failure = "size " + size + ": measuring the graded panels: " + e.what();
      }
    }
    if (failure) {
      if (policy == SizeRunPolicy::allOrNothing)
        return Error{*failure};
      run.skipped.push_back(*failure);
      continue;
    }
    run.sizes.push_back(size);
    run.patterns.push_back(std::move(graded).value());
    run.garment.push_back(std::move(garment));
    run.body.push_back(chart.bodies[i].values());
  }
  if (run.sizes.empty())
    return Error{
        "no size of chart " + chart.name + " could be graded: " +
        (run.skipped.empty() ? std::string("the chart has no sizes") : run.skipped.front())};
  return run;
}

}  // namespace garmcap::dsw
