// Garments drafted by the project's recipes: kept in its own unit so that code which only renders
// given measurements does not link the recipes.
#include <stdexcept>

#include "garmcap/calib/garment_model.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"

namespace garmcap::calib {

std::map<std::string, double> garmentFromDraft(const std::string& type,
                                               const std::map<std::string, std::string>& attributes,
                                               const drafts::Measurements& body,
                                               std::string* recipeUsed) {
  const auto& names = garmentMeasurementNames(type);
  // The recipe whose name is the type, or starts with it (e.g. "skirt_a" for an a_line skirt).
  std::string recipe;
  const auto sk = attributes.find("skirt");
  std::vector<std::string> candidates = {type};
  if (sk != attributes.end()) {
    candidates.insert(candidates.begin(), type + (sk->second == "a_line" ? "_a" : "_h"));
    candidates.insert(candidates.begin(), type + "_" + sk->second);
  }
  if (type == "top")
    candidates.insert(candidates.end(), {"bodice", "blouse", "shirt"});
  if (type == "pants")
    candidates.push_back("trousers");
  for (const auto& c : candidates) {
    for (const auto& info : drafts::garmentTypes()) {
      if (info.name == c) {
        recipe = c;
        break;
      }
    }
    if (!recipe.empty())
      break;
  }
  if (recipe.empty()) {
    std::string known;
    for (const auto& info : drafts::garmentTypes())
      known += (known.empty() ? "" : ", ") + info.name;
    throw std::invalid_argument("no draft recipe for a " + type + " (recipes: " + known + ")");
  }
  std::map<std::string, double> design;
  const auto sl = attributes.find("sleeve");
  for (const auto& p : drafts::garmentType(recipe).design) {
    if (sl != attributes.end() && p.name == "sleeve_length") {
      design[p.name] =
          sl->second == "none" ? p.minValue : (sl->second == "short" ? 22.0 : p.defaultValue);
    }
  }
  const drafts::Pattern pattern = drafts::draftGarment(recipe, body, design);
  const auto measured = drafts::measurePattern(pattern);
  std::map<std::string, double> out;
  for (const auto& n : names) {
    const auto it = measured.find(n);
    if (it != measured.end()) {
      out[n] = it->second;
    } else if (n == "sleeve_length" && sl != attributes.end() && sl->second == "none") {
      out[n] = 0;
    } else {
      throw std::invalid_argument("the " + recipe + " draft does not give '" + n + "'");
    }
  }
  if (recipeUsed)
    *recipeUsed = recipe;
  return out;
}

}  // namespace garmcap::calib
