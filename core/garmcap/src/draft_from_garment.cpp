#include "garmcap/pipeline/draft_from_garment.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "garmcap/drafts/recipes.h"

namespace garmcap::pipeline {
namespace {

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

// A dress whose waist takes in less than this from its bust is drafted as a shift (no waist
// seam): the darted one-piece dress spreads (bust - waist) / 2 over six Bunka darts, the smallest
// (7 %) then under 0.2 cm and the largest (35 %) about 1 cm, and it refuses a waist that does not
// stay 2 cm under the bust at all (docs/drafts.md, "Shift dress").
constexpr double kShiftMaxWaistSuppressionCm = 6.0;

// Bunka's bust ease, the darted dress's default: a dress whose bust was not read is taken to have
// it over the form's bust.
constexpr double kDressDefaultBustEaseCm = 12.0;

bool isShift(const std::map<std::string, double>& g, const drafts::Measurements& body) {
  const auto bust = g.find("bust_circ"), waist = g.find("waist_circ");
  if (waist == g.end())
    return false;
  std::optional<double> b;
  if (bust != g.end())
    b = bust->second;
  else if (body.has("bust_circ"))
    b = body.get("bust_circ") + kDressDefaultBustEaseCm;
  return b && *b - waist->second < kShiftMaxWaistSuppressionCm;
}

}  // namespace

DraftChoice chooseDraft(const std::string& type,
                        const std::map<std::string, std::string>& attributes,
                        const std::map<std::string, double>& g, const drafts::Measurements& body,
                        double sideNeckToWaistCm, std::vector<std::string>& warnings) {
  DraftChoice c;
  auto attr = [&](const std::string& k) {
    const auto it = attributes.find(k);
    return it == attributes.end() ? std::string() : it->second;
  };
  if (type == "top")
    c.recipe = "blouse";
  else if (type == "dress")
    c.recipe = isShift(g, body) ? "dress_shift" : "dress";
  else if (type == "skirt")
    c.recipe = attr("skirt") == "a_line" ? "skirt_a" : "skirt_h";
  else if (type == "pants")
    c.recipe = "pants";
  else
    throw std::invalid_argument("no draft for garment type '" + type + "'");

  auto has = [&](const std::string& n) { return g.count(n) != 0; };
  auto ease = [&](const std::string& garmentName, const std::string& param) {
    if (has(garmentName) && body.has(garmentName))
      c.design[param] = g.at(garmentName) - body.get(garmentName);
  };
  ease("bust_circ", "ease_bust");
  ease("waist_circ", "ease_waist");
  ease("hip_circ", "ease_hip");
  if (has("skirt_length"))
    c.design["skirt_length"] = g.at("skirt_length");
  if (has("hem_circ") && (type == "skirt" || type == "dress") && has("hip_circ"))
    c.design["hem_flare"] = (g.at("hem_circ") - g.at("hip_circ")) / 4.0;
  if (type == "top") {
    if (has("garment_length"))
      c.design["blouse_length"] = g.at("garment_length") - sideNeckToWaistCm;
    // A top's hem is below the waist: its hem circumference stands for the hip ease.
    if (has("hem_circ") && body.has("hip_circ"))
      c.design["ease_hip"] = g.at("hem_circ") - body.get("hip_circ");
  }
  if (has("sleeve_length") && body.has("arm_shoulder_tip_to_wrist"))
    c.design["sleeve_length"] = g.at("sleeve_length") / body.get("arm_shoulder_tip_to_wrist");
  else if (attr("sleeve") == "none")
    c.design["sleeve_length"] = 0.0;  // a torso form has no arm to read a length on
  if (type == "pants") {
    if (has("outseam") && body.has("leg_waist_side_to_floor"))
      c.design["pants_length"] = g.at("outseam") / body.get("leg_waist_side_to_floor");
    // Front leg hem width; the back is 2 cm wider (recipe), so front + back = opening.
    if (has("leg_opening_circ"))
      c.design["hem_width"] = (g.at("leg_opening_circ") - 2.0) / 2.0;
  }

  // Keep to the recipe's ranges, and say where the photo asked for something it cannot draw.
  const auto& info = drafts::garmentType(c.recipe);
  for (auto it = c.design.begin(); it != c.design.end();) {
    const auto p = std::find_if(info.design.begin(), info.design.end(),
                                [&](const auto& d) { return d.name == it->first; });
    if (p == info.design.end()) {
      it = c.design.erase(it);
      continue;
    }
    const double clamped = std::clamp(it->second, p->minValue, p->maxValue);
    if (std::abs(clamped - it->second) > 1e-9) {
      warnings.push_back("draft: " + it->first + " " + fmt(it->second) + " is outside the " +
                         c.recipe + " recipe's range [" + fmt(p->minValue) + ", " +
                         fmt(p->maxValue) + "]; drafted with " + fmt(clamped));
      it->second = clamped;
    }
    ++it;
  }
  return c;
}

drafts::Pattern draftFromGarment(const std::string& type,
                                 const std::map<std::string, std::string>& attributes,
                                 const std::map<std::string, double>& garment,
                                 const drafts::Measurements& body, double sideNeckToWaistCm,
                                 std::vector<std::string>& warnings) {
  const DraftChoice c = chooseDraft(type, attributes, garment, body, sideNeckToWaistCm, warnings);
  return drafts::draftGarment(c.recipe, body, c.design);
}

}  // namespace garmcap::pipeline
