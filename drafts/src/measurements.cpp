// Measurement vocabulary, measurements JSON, Valentina .vit reader/writer and .vst writer.

#include "garmcap/drafts/measurements.h"

#include <charconv>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/drafts/xml_escape.h"
#include "measurements_vocabulary.h"
#include "xml_reader.h"

namespace garmcap::drafts {

namespace {

// Project-specific names: values the seed's tables list as primary body sizes that have no
// Valentina known measurement. Written to .vit files as Valentina custom measurements
// ("@name"), read back from them under the plain name.
const std::vector<MeasurementInfo>& projectMeasurements() {
  static const std::vector<MeasurementInfo> kProject = {
      {"skirt_length",
       "Skirt length: the garment's length from the waist to the hem at the side (seed tables "
       "4.2 and 5.1 list it among the primary body sizes). A garment value, not a body "
       "measurement; recipes take it as their skirt_length design parameter.",
       false},
      {"front_armhole_circ",
       "Front armhole circumference: length of the front armhole curve from the shoulder tip to "
       "the underarm point, as listed in seed table 4.2 (measured on the draft/panels, table "
       "4.3). front_armhole_circ + back_armhole_circ = armscye_circ of the same body.",
       false},
      {"back_armhole_circ",
       "Back (rear) armhole circumference: length of the back armhole curve from the shoulder "
       "tip to the underarm point, as listed in seed table 4.2.",
       false},
  };
  return kProject;
}

const std::unordered_map<std::string, const MeasurementInfo*>& vocabularyIndex() {
  static const auto kIndex = [] {
    std::unordered_map<std::string, const MeasurementInfo*> index;
    for (const auto& m : measurementVocabulary())
      index.emplace(m.name, &m);
    return index;
  }();
  return kIndex;
}

bool isProjectMeasurement(const std::string& name) {
  const auto it = vocabularyIndex().find(name);
  return it != vocabularyIndex().end() && !it->second->valentinaKnown;
}

// Valentina's angle measurements are in degrees whatever the file unit.
bool isAngle(const std::string& name) {
  return name.size() > 6 && name.compare(name.size() - 6, 6, "_angle") == 0;
}

// Shortest text that reads back to exactly the same double.
std::string formatNumber(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

void checkValue(const std::string& where, const std::string& name, double v) {
  if (!std::isfinite(v))
    throw ParseError(where + ": measurement '" + name + "' is not finite");
  if (v < 0) {
    throw ParseError(where + ": measurement '" + name + "' is negative (" + formatNumber(v) +
                     " cm)");
  }
}

void checkWritable(const Measurements& m, const char* function) {
  for (const auto& [name, v] : m.values()) {
    if (!isKnownMeasurement(name)) {
      throw std::invalid_argument(std::string(function) + ": unknown measurement '" + name + "'");
    }
    if (!std::isfinite(v) || v < 0) {
      throw std::invalid_argument(std::string(function) + ": measurement '" + name +
                                  "' has an invalid value " + formatNumber(v));
    }
  }
}

std::string vitPlace(const std::string& what, const detail::XmlElement& e) {
  return what + ": line " + std::to_string(e.line) + ", column " + std::to_string(e.column) +
         " (<" + e.name + ">)";
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos)
    return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

}  // namespace

// ---- Measurements --------------------------------------------------------------------------

double Measurements::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end())
    throw std::out_of_range("measurement '" + name + "' is missing");
  return it->second;
}

std::optional<double> Measurements::find(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end())
    return std::nullopt;
  return it->second;
}

Measurements Measurements::scaled(double factor) const {
  Measurements out;
  for (const auto& [name, v] : values_) {
    // Angles describe shape, not size: scaling the body keeps them.
    out.set(name, isAngle(name) ? v : v * factor);
  }
  return out;
}

// ---- vocabulary ----------------------------------------------------------------------------

const std::vector<MeasurementInfo>& measurementVocabulary() {
  static const std::vector<MeasurementInfo> kAll = [] {
    std::vector<MeasurementInfo> all;
    for (const auto& k : detail::valentinaKnownMeasurements()) {
      all.push_back({k.name,
                     std::string(k.fullName) + " (Valentina " + k.code + "). " + k.description,
                     true});
    }
    for (const auto& p : projectMeasurements())
      all.push_back(p);
    return all;
  }();
  return kAll;
}

bool isKnownMeasurement(const std::string& name) {
  return vocabularyIndex().count(name) != 0;
}

// ---- measurements JSON ---------------------------------------------------------------------

Measurements measurementsFromJson(const std::string& text, const std::string& what) {
  nlohmann::json doc;
  try {
    doc = parseJson(text, what);
  } catch (const nlohmann::json::exception& e) {
    // parseJson turns syntax errors into ParseError; a number too large for a double
    // ("1e999") reaches us as nlohmann's out_of_range.
    throw ParseError(what + ": malformed JSON: " + e.what());
  }
  if (!doc.is_object())
    throw ParseError(what + ": expected a JSON object at the top level");
  for (const auto& [key, value] : doc.items()) {
    (void)value;
    if (key != "units" && key != "measurements") {
      throw ParseError(what + ": unknown field '" + key +
                       "' (expected 'units' and 'measurements')");
    }
  }
  const std::string units = requireString(doc, "units", what);
  if (units != "cm") {
    throw ParseError(what + ": field 'units' is '" + units + "'; measurements JSON is in \"cm\"");
  }
  const auto& values = requireField(doc, "measurements", what);
  if (!values.is_object())
    throw ParseError(what + ": field 'measurements' must be an object");
  Measurements m;
  const std::string where = what + ": measurements";
  for (const auto& [name, value] : values.items()) {
    if (!isKnownMeasurement(name)) {
      throw ParseError(what + ": unknown measurement 'measurements." + name +
                       "' (not a Valentina known measurement nor a project name; see "
                       "docs/formats.md)");
    }
    const double v = requireNumber(values, name, where);
    checkValue(what, "measurements." + name, v);
    m.set(name, v);
  }
  return m;
}

Measurements readMeasurementsJson(const std::filesystem::path& path) {
  return measurementsFromJson(readFile(path), path.string());
}

std::string measurementsToJson(const Measurements& m) {
  checkWritable(m, "measurementsToJson");
  nlohmann::json values = nlohmann::json::object();
  for (const auto& [name, v] : m.values())
    values[name] = v;
  nlohmann::json doc = nlohmann::json::object();
  doc["units"] = "cm";
  doc["measurements"] = values;
  return doc.dump(2) + "\n";
}

void writeMeasurementsJson(const std::filesystem::path& path, const Measurements& m) {
  writeFileAtomic(path, measurementsToJson(m));
}

// ---- Valentina .vit ------------------------------------------------------------------------

Measurements measurementsFromVit(const std::string& xml, const std::string& what) {
  const detail::XmlElement root = detail::parseXml(xml, what);
  if (root.name != "vit") {
    throw ParseError(vitPlace(what, root) + ": root element is <" + root.name +
                     ">, expected <vit> (a Valentina individual measurements file)");
  }
  const auto* version = root.child("version");
  if (!version)
    throw ParseError(vitPlace(what, root) + ": missing <version>");
  {
    // Versions 0.2.0 (Valentina 0.4) to 0.6.x (Valentina 1.x) share the parts read here.
    const std::string v = trim(version->text);
    int major = -1, minor = -1, patch = -1;
    char dot1 = 0, dot2 = 0;
    std::istringstream in(v);
    in >> major >> dot1 >> minor >> dot2 >> patch;
    if (!in || dot1 != '.' || dot2 != '.' || !in.eof() || major < 0 || minor < 0 || patch < 0) {
      throw ParseError(vitPlace(what, *version) + ": version '" + v + "' is not major.minor.patch");
    }
    if (major != 0 || minor > 6 || (minor < 2)) {
      throw ParseError(vitPlace(what, *version) + ": .vit format version " + v +
                       " is not supported (0.2.0 to 0.6.x are)");
    }
  }
  const auto* unitElement = root.child("unit");
  if (!unitElement)
    throw ParseError(vitPlace(what, root) + ": missing <unit>");
  const std::string unit = trim(unitElement->text);
  double toCm = 1.0;
  if (unit == "cm")
    toCm = 1.0;
  else if (unit == "mm")
    toCm = 0.1;
  else if (unit == "inch")
    toCm = 2.54;
  else
    throw ParseError(vitPlace(what, *unitElement) + ": unit '" + unit + "' is not mm, cm or inch");

  const auto* body = root.child("body-measurements");
  if (!body)
    throw ParseError(vitPlace(what, root) + ": missing <body-measurements>");
  Measurements m;
  std::set<std::string> seen;
  for (const auto& e : body->children) {
    if (e.name != "m") {
      throw ParseError(vitPlace(what, e) + ": unexpected element in <body-measurements>");
    }
    if (const auto* type = e.attribute("type"); type && *type == "separator")
      continue;
    const auto* nameAttr = e.attribute("name");
    if (!nameAttr || nameAttr->empty())
      throw ParseError(vitPlace(what, e) + ": <m> without a name");
    std::string name = *nameAttr;
    if (!seen.insert(name).second) {
      throw ParseError(vitPlace(what, e) + ": measurement '" + name + "' appears twice");
    }
    if (name[0] == '@') {
      // A Valentina custom measurement: ours when it carries a project name, otherwise the
      // wearer's private note for their own patterns, which no recipe reads (documented in
      // docs/formats.md).
      const std::string plain = name.substr(1);
      if (!isProjectMeasurement(plain))
        continue;
      name = plain;
    } else if (!isKnownMeasurement(name) || isProjectMeasurement(name)) {
      throw ParseError(vitPlace(what, e) + ": unknown measurement '" + name +
                       "' (not a Valentina known measurement)");
    }
    const auto* valueAttr = e.attribute("value");
    if (!valueAttr)
      throw ParseError(vitPlace(what, e) + ": measurement '" + name + "' has no value");
    const std::string text = trim(*valueAttr);
    double v = 0;
    const auto res = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || res.ec != std::errc() || res.ptr != text.data() + text.size()) {
      throw ParseError(vitPlace(what, e) + ": value '" + *valueAttr + "' of measurement '" + name +
                       "' is not a number (formulas are not supported)");
    }
    if (!std::isfinite(v)) {
      throw ParseError(vitPlace(what, e) + ": value of measurement '" + name + "' is not finite");
    }
    if (v < 0) {
      throw ParseError(vitPlace(what, e) + ": measurement '" + name + "' is negative (" + text +
                       ")");
    }
    m.set(name, isAngle(name) ? v : v * toCm);
  }
  return m;
}

Measurements readVit(const std::filesystem::path& path) {
  return measurementsFromVit(readFile(path), path.string());
}

std::string measurementsToVit(const Measurements& m) {
  checkWritable(m, "measurementsToVit");
  std::ostringstream out;
  // Format 0.5.1 (what Valentina 0.7.x writes); newer Valentina converts it on open.
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<vit>\n"
      << "    <!--Measurements created with GarmCap Station.-->\n"
      << "    <version>0.5.1</version>\n"
      << "    <read-only>false</read-only>\n"
      << "    <notes/>\n"
      << "    <unit>cm</unit>\n"
      << "    <pm_system>998</pm_system>\n"
      << "    <personal>\n"
      << "        <customer/>\n"
      << "        <birth-date>1800-01-01</birth-date>\n"
      << "        <gender>unknown</gender>\n"
      << "        <email/>\n"
      << "    </personal>\n"
      << "    <body-measurements>\n";
  for (const auto& [name, v] : m.values()) {
    if (isProjectMeasurement(name)) {
      const auto* info = vocabularyIndex().at(name);
      out << "        <m name=\"@" << xmlEscape(name) << "\" value=\"" << formatNumber(v)
          << "\" full_name=\"" << xmlEscape(name) << "\" description=\""
          << xmlEscape(info->description) << "\"/>\n";
    } else {
      out << "        <m name=\"" << xmlEscape(name) << "\" value=\"" << formatNumber(v)
          << "\"/>\n";
    }
  }
  out << "    </body-measurements>\n</vit>\n";
  return out.str();
}

namespace {

// Rounded to 1e-6 cm so that the shortest decimal of the double is the clean one (0.6, not
// 0.6000000000000014): Valentina reads the numbers as text.
double round6(double v) {
  return std::round(v * 1e6) / 1e6;
}

// The values of the chart's "Size" dimension: the sizes themselves when they are numbers evenly
// spaced by a step Valentina accepts (1 to 50 in tenths, a whole number of steps from the
// smallest to the largest, all within the 1..100 of a dimension that is not a body
// measurement), else the positions 1..N.
std::vector<double> dimensionValues(const SizeChart& chart) {
  std::vector<double> values;
  for (const auto& size : chart.sizes) {
    double v = 0;
    const auto res = std::from_chars(size.data(), size.data() + size.size(), v);
    if (res.ec != std::errc() || res.ptr != size.data() + size.size())
      break;
    values.push_back(v);
  }
  bool usable = values.size() == chart.sizes.size() && !values.empty();
  if (usable && values.size() > 1) {
    const double step = (values.back() - values.front()) / static_cast<double>(values.size() - 1);
    usable = step >= 1 && step < 50 && std::abs(step * 10 - std::round(step * 10)) < 1e-9;
    for (size_t i = 0; usable && i < values.size(); ++i)
      usable = std::abs(values[i] - (values.front() + step * static_cast<double>(i))) < 1e-9;
  }
  for (double v : values)
    usable = usable && v >= 1 && v <= 100;
  if (!usable) {
    values.clear();
    for (size_t i = 0; i < chart.sizes.size(); ++i)
      values.push_back(static_cast<double>(i + 1));
  }
  return values;
}

}  // namespace

std::string chartToVst(const SizeChart& chart) {
  const std::string where = "chartToVst(" + chart.name + ")";
  if (chart.sizes.empty() || chart.sizes.size() != chart.bodies.size())
    throw std::invalid_argument(where + ": the chart has no sizes or not one body per size");
  for (const auto& body : chart.bodies)
    checkWritable(body, "chartToVst");
  const size_t n = chart.sizes.size();
  for (size_t i = 0; i < n; ++i) {
    for (const auto& [name, v] : chart.bodies.front().values()) {
      if (!chart.bodies[i].has(name)) {
        throw std::invalid_argument(where + ": measurement '" + name + "' is missing in size " +
                                    chart.sizes[i]);
      }
    }
    if (chart.bodies[i].values().size() != chart.bodies.front().values().size()) {
      throw std::invalid_argument(where + ": size " + chart.sizes[i] +
                                  " has measurements that size " + chart.sizes.front() + " lacks");
    }
  }
  const std::vector<double> dims = dimensionValues(chart);
  const size_t baseIndex = n / 2;
  const double step = n > 1 ? (dims.back() - dims.front()) / static_cast<double>(n - 1) : 0.0;
  std::ostringstream out;
  // Format 0.5.4, the newest multisize format Valentina 0.7.52 reads (its own schema list).
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<vst>\n"
      << "    <!--Measurements created with GarmCap Station.-->\n"
      << "    <version>0.5.4</version>\n"
      << "    <read-only>false</read-only>\n"
      << "    <notes>" << xmlEscape("Size chart " + chart.name + ". " + chart.source)
      << "</notes>\n"
      << "    <unit>cm</unit>\n"
      << "    <pm_system>998</pm_system>\n"
      << "    <dimensions>\n"
      << "        <dimension type=\"y\" base=\"" << formatNumber(dims[baseIndex]) << "\" min=\""
      << formatNumber(dims.front()) << "\" max=\"" << formatNumber(dims.back()) << "\" step=\""
      << formatNumber(round6(step)) << "\" measurement=\"false\" customName=\"Size\">\n"
      << "            <labels>\n";
  for (size_t i = 0; i < n; ++i) {
    out << "                <label value=\"" << formatNumber(dims[i]) << "\" label=\""
        << xmlEscape(chart.sizes[i]) << "\"/>\n";
  }
  out << "            </labels>\n"
      << "        </dimension>\n"
      << "    </dimensions>\n"
      << "    <restrictions/>\n"
      << "    <body-measurements>\n";
  for (const auto& [name, unused] : chart.bodies.front().values()) {
    // Valentina's value at size value d: base + (d - base d) / step * shiftA + correction(d).
    const double base = chart.bodies[baseIndex].get(name);
    const double shift =
        n > 1 ? round6((chart.bodies.back().get(name) - chart.bodies.front().get(name)) /
                       static_cast<double>(n - 1))
              : 0.0;
    std::string corrections;
    for (size_t i = 0; i < n; ++i) {
      const double k = static_cast<double>(i) - static_cast<double>(baseIndex);
      const double correction = round6(chart.bodies[i].get(name) - (base + k * shift));
      if (correction != 0.0) {
        corrections += "                <correction coordinates=\"" + formatNumber(dims[i]) +
                       "\" correction=\"" + formatNumber(correction) + "\"/>\n";
      }
    }
    const bool project = isProjectMeasurement(name);
    out << "        <m name=\"" << (project ? "@" : "") << xmlEscape(name) << "\" base=\""
        << formatNumber(base) << "\" shiftA=\"" << formatNumber(shift) << "\"";
    if (project) {
      out << " full_name=\"" << xmlEscape(name) << "\" description=\""
          << xmlEscape(vocabularyIndex().at(name)->description) << "\"";
    }
    if (corrections.empty()) {
      out << "/>\n";
    } else {
      out << ">\n            <corrections>\n"
          << corrections << "            </corrections>\n        </m>\n";
    }
  }
  out << "    </body-measurements>\n</vst>\n";
  return out.str();
}

void writeVit(const std::filesystem::path& path, const Measurements& m) {
  writeFileAtomic(path, measurementsToVit(m));
}

Measurements readMeasurementsFile(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".vit")
    return readVit(path);
  if (ext == ".json")
    return readMeasurementsJson(path);
  throw ParseError(path.string() + ": unknown measurements file type '" + ext +
                   "' (expected .json or .vit)");
}

}  // namespace garmcap::drafts
