#pragma once
// Body measurements by Valentina/Seamly2D known-measurement name, in centimetres.
// Files: measurements JSON ({"units": "cm", "measurements": {...}}) and Valentina individual
// measurement files (.vit). See docs/formats.md.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace garmcap::drafts {

/// A set of named measurements in cm. Names are Valentina known-measurement names
/// (`bust_circ`, `waist_circ`, `neck_back_to_waist_b`, ...); see measurementVocabulary().
class Measurements {
 public:
  Measurements() = default;
  explicit Measurements(std::map<std::string, double> values) : values_(std::move(values)) {}

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// Value in cm; throws std::out_of_range naming the measurement when it is absent.
  double get(const std::string& name) const;
  std::optional<double> find(const std::string& name) const;
  void set(const std::string& name, double valueCm) { values_[name] = valueCm; }
  const std::map<std::string, double>& values() const { return values_; }
  bool empty() const { return values_.empty(); }

  /// Every value multiplied by `factor` (used for body-scale sweeps).
  Measurements scaled(double factor) const;

  friend bool operator==(const Measurements&, const Measurements&) = default;

 private:
  std::map<std::string, double> values_;
};

/// One entry of the measurement vocabulary.
struct MeasurementInfo {
  std::string name;         // Valentina name, e.g. "bust_circ"
  std::string description;  // what it is and how it is taken
  bool valentinaKnown = true;  // false for project-specific names (documented in docs/)
};

/// Every measurement name the project reads or writes.
const std::vector<MeasurementInfo>& measurementVocabulary();
bool isKnownMeasurement(const std::string& name);

/// Measurements JSON. Readers throw ParseError naming the file and the field (unknown name,
/// non-number, non-finite, units other than "cm").
Measurements measurementsFromJson(const std::string& text, const std::string& what);
Measurements readMeasurementsJson(const std::filesystem::path& path);
std::string measurementsToJson(const Measurements& m);
void writeMeasurementsJson(const std::filesystem::path& path, const Measurements& m);

/// Valentina individual measurement file (.vit, XML). Reads format versions 0.2.0-0.6.x
/// (Valentina 0.4 to 1.x); writes 0.5.1 (what Valentina 0.7.x writes). mm and inch files are
/// converted to cm. Readers throw ParseError naming the file, line and column.
Measurements measurementsFromVit(const std::string& xml, const std::string& what);
Measurements readVit(const std::filesystem::path& path);
std::string measurementsToVit(const Measurements& m);
void writeVit(const std::filesystem::path& path, const Measurements& m);

/// Reads .vit or .json by extension.
Measurements readMeasurementsFile(const std::filesystem::path& path);

}  // namespace garmcap::drafts
