#include "garmcap/dsw/size_guide.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/dsw/csv.h"

namespace garmcap::dsw {
namespace {

// The chart body circumferences a shopper compares with her own.
const std::vector<std::string> kBodyNames = {"bust_circ", "waist_circ", "hip_circ"};

std::optional<double> find(const std::map<std::string, double>& m, const std::string& name) {
  const auto it = m.find(name);
  return it == m.end() ? std::nullopt : std::optional<double>(it->second);
}

// What in a graded pattern's measurements moves as the garment measurement `name` does. Values
// are absolute where the pattern shows the measurement itself; a top's length is its neck to
// waist plus a blouse length the grading keeps, so only its change is meaningful.
std::optional<double> gradedCounterpart(const std::string& type, const std::string& name,
                                        const std::map<std::string, double>& pattern) {
  if (type == "pants") {
    if (name == "outseam")
      return find(pattern, "outseam_length");
    if (name == "inseam")
      return find(pattern, "inseam_length");
    if (name == "leg_opening_circ")
      return find(pattern, "hem_circ");
    if (name == "hem_circ")
      return std::nullopt;
  }
  if (name == "garment_length") {
    const auto neck = find(pattern, "neck_back_to_waist_b");
    if (type == "top")
      return neck;
    const auto skirt = find(pattern, "skirt_length");
    if (type == "dress" && neck && skirt)
      return *neck + *skirt;
    return std::nullopt;
  }
  return find(pattern, name);
}

double round3(double v) {
  return std::round(v * 1000.0) / 1000.0;
}

std::string formatCm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", std::round(v * 10.0) / 10.0);
  return buf;
}

nlohmann::json cmObject(const std::map<std::string, double>& m) {
  nlohmann::json o = nlohmann::json::object();
  for (const auto& [k, v] : m)
    o[k] = round3(v);
  return o;
}

std::map<std::string, double> cmFromJson(const nlohmann::json& o, const std::string& what) {
  if (!o.is_object())
    throw drafts::ParseError(what + " must be an object of cm values");
  std::map<std::string, double> out;
  for (const auto& [k, v] : o.items()) {
    if (!v.is_number())
      throw drafts::ParseError(what + ": '" + k + "' must be a number (cm)");
    out[k] = v.get<double>();
  }
  return out;
}

}  // namespace

const std::vector<std::string>& sizeGuideMeasurementNames() {
  static const std::vector<std::string> kNames = {
      "bust_circ",    "waist_circ",    "hip_circ", "hem_circ", "garment_length",
      "skirt_length", "sleeve_length", "outseam",  "inseam",   "leg_opening_circ"};
  return kNames;
}

std::string measurementLabel(const std::string& name) {
  static const std::map<std::string, std::string> kLabels = {{"bust_circ", "Bust"},
                                                             {"waist_circ", "Waist"},
                                                             {"hip_circ", "Hip"},
                                                             {"hem_circ", "Hem"},
                                                             {"garment_length", "Length"},
                                                             {"skirt_length", "Skirt length"},
                                                             {"sleeve_length", "Sleeve length"},
                                                             {"outseam", "Outseam"},
                                                             {"inseam", "Inseam"},
                                                             {"leg_opening_circ", "Leg opening"}};
  if (const auto it = kLabels.find(name); it != kLabels.end())
    return it->second;
  std::string out = name;
  for (char& c : out)
    if (c == '_')
      c = ' ';
  if (!out.empty())
    out[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(out[0])));
  return out;
}

std::optional<std::string> garmentTypeOfRecipe(const std::string& recipe) {
  if (recipe == "blouse" || recipe == "bodice" || recipe == "sweater")
    return "top";
  if (recipe == "skirt_a" || recipe == "skirt_h" || recipe == "skirt_high_waist")
    return "skirt";
  if (recipe == "dress" || recipe == "dress_shift")
    return "dress";
  if (recipe == "pants")
    return recipe;
  return std::nullopt;
}

std::optional<std::map<std::string, double>> bodyFittedBy(
    const std::string& recipe, const std::map<std::string, double>& garmentCm) {
  const drafts::GarmentTypeInfo* info = nullptr;
  for (const auto& t : drafts::garmentTypes())
    if (t.name == recipe)
      info = &t;
  if (!info)
    return std::nullopt;
  auto easeOf = [&](const std::string& param) -> std::optional<double> {
    for (const auto& d : info->design)
      if (d.name == param)
        return d.defaultValue;
    return std::nullopt;
  };
  std::map<std::string, double> body;
  auto take = [&](const std::string& garmentName, const std::string& bodyName,
                  const std::string& param) {
    const auto g = find(garmentCm, garmentName);
    const auto e = easeOf(param);
    if (g && e && !body.count(bodyName))
      body[bodyName] = *g - *e;
  };
  take("bust_circ", "bust_circ", "ease_bust");
  take("waist_circ", "waist_circ", "ease_waist");
  take("hip_circ", "hip_circ", "ease_hip");
  if (garmentTypeOfRecipe(recipe) == std::optional<std::string>("top"))
    take("hem_circ", "hip_circ", "ease_hip");  // the recipe drafts a top's hem on the hip
  return body;
}

std::optional<std::size_t> nearestChartSize(const drafts::SizeChart& chart,
                                            const std::map<std::string, double>& bodyCm) {
  std::optional<std::size_t> best;
  double bestMs = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < chart.sizes.size(); ++i) {
    double d2 = 0;
    int n = 0;
    for (const auto& [name, cm] : bodyCm)
      if (chart.bodies[i].has(name)) {
        const double d = chart.bodies[i].get(name) - cm;
        d2 += d * d;
        ++n;
      }
    if (n > 0 && d2 / n < bestMs) {
      bestMs = d2 / n;
      best = i;
    }
  }
  return best;
}

std::optional<std::size_t> sampleSizeOf(const drafts::Pattern& draft,
                                        const drafts::SizeChart& chart) {
  std::map<std::string, double> body;
  for (const auto& name : kBodyNames)
    if (const auto v = draft.measurements.find(name))
      body[name] = *v;
  if (body.empty())
    return std::nullopt;
  return nearestChartSize(chart, body);
}

std::map<std::string, double> shopperMeasurements(const std::string& type,
                                                  const std::map<std::string, double>& patternCm) {
  std::map<std::string, double> out;
  for (const auto& name : sizeGuideMeasurementNames()) {
    // A top's length is not on its pattern as an absolute value (see gradedCounterpart).
    if (type == "top" && name == "garment_length")
      continue;
    if (const auto v = gradedCounterpart(type, name, patternCm))
      out[name] = *v;
  }
  return out;
}

Expected<SizeGuide> buildSizeGuide(const SizeRun& run, const drafts::SizeChart& chart,
                                   const std::string& type,
                                   const std::map<std::string, double>& itemCm,
                                   std::size_t itemSize) {
  if (itemSize >= run.sizes.size())
    return Error{"size guide: the item's size index " + std::to_string(itemSize) +
                 " is outside the run of " + std::to_string(run.sizes.size()) + " sizes"};
  SizeGuide g;
  g.type = type;
  g.chart = chart.name;
  for (const auto& name : sizeGuideMeasurementNames())
    if (const auto v = find(itemCm, name); v && *v > 0)
      g.measurements.push_back(name);
  if (g.measurements.empty())
    return Error{"size guide: the item has none of the measurements a size guide shows"};
  const auto& base = run.garment[itemSize];
  for (std::size_t i = 0; i < run.sizes.size(); ++i) {
    SizeGuideRow row;
    row.size = run.sizes[i];
    for (const auto& name : g.measurements) {
      const double own = itemCm.at(name);
      if (i == itemSize) {
        row.garmentCm[name] = own;
        continue;
      }
      const auto here = gradedCounterpart(type, name, run.garment[i]);
      const auto there = gradedCounterpart(type, name, base);
      if (here && there)
        row.garmentCm[name] = own + (*here - *there);
    }
    for (const auto& name : kBodyNames)
      if (const auto v = find(run.body[i], name))
        row.bodyCm[name] = *v;
    g.rows.push_back(std::move(row));
  }
  g.itemRow = itemSize;
  return g;
}

SizeGuide singleSizeGuide(const std::string& type, const std::string& chart,
                          const std::string& size, const std::map<std::string, double>& itemCm) {
  SizeGuide g;
  g.type = type;
  g.chart = chart;
  SizeGuideRow row;
  row.size = size;
  for (const auto& name : sizeGuideMeasurementNames())
    if (const auto v = find(itemCm, name); v && *v > 0) {
      g.measurements.push_back(name);
      row.garmentCm[name] = *v;
    }
  g.rows.push_back(std::move(row));
  return g;
}

std::string sizeGuideJson(const SizeGuide& guide) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : guide.rows)
    rows.push_back(
        {{"size", r.size}, {"garment", cmObject(r.garmentCm)}, {"body", cmObject(r.bodyCm)}});
  return nlohmann::json{{"units", "cm"},
                        {"type", guide.type},
                        {"chart", guide.chart},
                        {"base_size", guide.rows.empty() ? std::string() : guide.itemSize()},
                        {"measurements", guide.measurements},
                        {"rows", rows}}
             .dump(2) +
         "\n";
}

SizeGuide sizeGuideFromJson(const std::string& text, const std::string& what) {
  const nlohmann::json j = drafts::parseJson(text, what);
  if (!j.is_object())
    throw drafts::ParseError(what + ": a size guide must be a JSON object");
  static const std::set<std::string> kFields = {"units",     "type",         "chart",
                                                "base_size", "measurements", "rows"};
  for (const auto& [k, v] : j.items())
    if (!kFields.count(k))
      throw drafts::ParseError(what + ": unknown field '" + k + "'");
  if (drafts::requireString(j, "units", what) != "cm")
    throw drafts::ParseError(what + ": field 'units' must be \"cm\"");
  SizeGuide g;
  g.type = drafts::requireString(j, "type", what);
  g.chart = drafts::requireString(j, "chart", what);
  const std::string base = drafts::requireString(j, "base_size", what);
  const auto& names = drafts::requireField(j, "measurements", what);
  if (!names.is_array())
    throw drafts::ParseError(what + ": field 'measurements' must be an array of names");
  for (const auto& n : names) {
    if (!n.is_string())
      throw drafts::ParseError(what + ": field 'measurements' must hold names (strings)");
    g.measurements.push_back(n.get<std::string>());
  }
  const auto& rows = drafts::requireField(j, "rows", what);
  if (!rows.is_array() || rows.empty())
    throw drafts::ParseError(what + ": field 'rows' must be a non-empty array");
  std::optional<std::size_t> itemRow;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string at = what + ": rows[" + std::to_string(i) + "]";
    if (!rows[i].is_object())
      throw drafts::ParseError(at + " must be an object");
    for (const auto& [k, v] : rows[i].items())
      if (k != "size" && k != "garment" && k != "body")
        throw drafts::ParseError(at + ": unknown field '" + k + "'");
    SizeGuideRow r;
    r.size = drafts::requireString(rows[i], "size", at);
    r.garmentCm = cmFromJson(drafts::requireField(rows[i], "garment", at), at + ": garment");
    r.bodyCm = cmFromJson(drafts::requireField(rows[i], "body", at), at + ": body");
    for (const auto& [k, v] : r.garmentCm)
      if (std::find(g.measurements.begin(), g.measurements.end(), k) == g.measurements.end())
        throw drafts::ParseError(at + ": garment: '" + k + "' is not in 'measurements'");
    if (r.size == base)
      itemRow = i;
    g.rows.push_back(std::move(r));
  }
  if (!itemRow)
    throw drafts::ParseError(what + ": field 'base_size' \"" + base + "\" names no row");
  g.itemRow = *itemRow;
  return g;
}

std::string sizeGuideCsv(const SizeGuide& guide) {
  std::string out = "size,item";
  for (const auto& name : guide.measurements)
    out += "," + csvField(name);
  out += "\r\n";
  for (std::size_t i = 0; i < guide.rows.size(); ++i) {
    const auto& r = guide.rows[i];
    out += csvField(r.size) + (i == guide.itemRow ? ",yes" : ",");
    for (const auto& name : guide.measurements) {
      out += ",";
      if (const auto v = find(r.garmentCm, name))
        out += formatCm(*v);
    }
    out += "\r\n";
  }
  return out;
}

}  // namespace garmcap::dsw
