#pragma once
// Draft recipes: D(garment type, body measurements, design parameters) -> Pattern, drawn step by
// step as a drafting book does, then panels derived from the draft.

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

/// A recipe refused its input: message names the recipe and the measurement or parameter.
class DraftError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DesignParameter {
  std::string name;
  double defaultValue = 0;
  double minValue = 0;
  double maxValue = 0;
  std::string description;  // units and meaning
  // A width the design sets in cm but a grader widens with the body: the body measurement it
  // grows with in proportion when the pattern is graded to another size (a trouser hem with the
  // hip). Empty: the value is kept in every size (ease, lengths below the waist, flare).
  std::string gradesWith{};
  // With gradesWith: the body value the default is designed for. Drafted without an explicit
  // value, the default then grows with the body in proportion too (defaultValue x body /
  // gradesFrom, clamped to the range), so every size of a chart gets its own width. 0: the
  // default is one value for every body.
  double gradesFrom = 0;
};

struct GarmentTypeInfo {
  std::string name;  // "bodice", "dress", "skirt_h", ...
  std::string description;
  std::vector<std::string> measurements;  // required body measurements (Valentina names)
  std::vector<DesignParameter> design;    // ease and design parameters with defaults
};

/// Every garment type with a recipe.
const std::vector<GarmentTypeInfo>& garmentTypes();
const GarmentTypeInfo& garmentType(const std::string& name);  // throws DraftError listing types

/// Draws the draft and derives its panels. `design` overrides defaults by name (unknown names
/// are refused). Throws DraftError for missing or absurd measurements.
Pattern draftGarment(const std::string& type, const Measurements& body,
                     const std::map<std::string, double>& design = {});

}  // namespace garmcap::drafts
