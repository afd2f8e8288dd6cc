#pragma once
// The shop's own tape measure (issue 15, part 7): staff tape a few garments once; per garment type
// and measurement the station fits a correction `corrected = scale * measured + offset` from the
// pairs (as measured by the pipeline, as taped) and applies it to later captures. It is how a
// method validated on renders comes to hold on a shop's real stock and fabrics.
//
// The rules (docs/measurement_model.md, "Tape corrections"):
// - fewer than kMinPairsForOffset pairs: no correction;
// - kMinPairsForOffset .. kMinPairsForScale-1 pairs: an offset, the MEDIAN of tape - measured
//   (with 3-5 garments one mis-read tape or one mis-typed number must not move every later capture;
//   the median of 3 ignores one outlier, the mean does not);
// - kMinPairsForScale or more: scale and offset by least squares, unless the scale is outside
//   [kMinPlausibleScale, kMaxPlausibleScale] or its leave-one-out residual is no better than the
//   offset's: then the offset (see fitCorrection);
// - a correction whose leave-one-out residual is no smaller than the raw error of its pairs is
//   fitted and listed but not applied: it does not predict a held-out garment better than the
//   pipeline's own reading does (unbiased errors leave an offset nothing to remove but noise; the
//   physical rig's bust, leave-one-out, read 2.29 cm raw and 2.76 corrected so);
// - nor one whose bias is not significant at the 5 % level (an offset: Student's t on
//   tape - measured; a scale and offset: the F test of the line against the identity): with
//   three garments an offset needs |mean| > 4.3 standard errors. Fitted on a handful of
//   garments, a bias small against its standard error is mostly their noise, and the
//   leave-one-out gain, itself estimated from the same few pairs, does not show that (reason
//   "not_significant").
// The residual reported is the leave-one-out one: each pair predicted by the correction fitted on
// the others, so it is the error a new garment can expect, not the fit's own (optimistic) error.
//
// Pure functions, no I/O; thread-safe.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace garmcap::pipeline {

inline constexpr int kMinPairsForOffset = 3;
inline constexpr int kMinPairsForScale = 6;
// The pipeline's errors on the rigs are offsets (landmarks placed a few cm off) and scale errors
// of a few per cent (px/cm from the registration, ease of the section). A least-squares slope
// beyond +-15 % says the taped garments span too narrow a range for a slope (all one size) or one
// pair is wrong, not that the method reads 20 % large: such a slope would extrapolate badly.
inline constexpr double kMinPlausibleScale = 0.85;
inline constexpr double kMaxPlausibleScale = 1.15;

/// One taped garment's measurement: what the pipeline read (uncorrected) and what staff taped.
struct TapePair {
  double measuredCm = 0;
  double tapeCm = 0;
};

enum class CorrectionKind { kOffset, kScaleOffset };

const char* toString(CorrectionKind kind);  // "offset" | "scale_offset"

struct Correction {
  CorrectionKind kind = CorrectionKind::kOffset;
  double scale = 1;         // 1 for kOffset
  double offsetCm = 0;      // corrected = scale * measured + offsetCm
  int n = 0;                // pairs it was fitted on
  double looMeanCm = 0;     // mean |leave-one-out residual| (the honest expected error)
  double looMaxCm = 0;      // max |leave-one-out residual|
  double rawMeanCm = 0;     // mean |tape - measured| of the pairs, uncorrected, for comparison
  bool significant = true;  // its bias (or line) is significant at 5 % (see fitCorrection)
  bool helps = true;        // looMeanCm < rawMeanCm and significant: only then is it applied

  double apply(double measuredCm) const { return scale * measuredCm + offsetCm; }
};

/// The correction for one (type, measurement) from its pairs; nullopt with fewer than
/// kMinPairsForOffset pairs. Pairs with a non-finite value are not counted (the API refuses
/// them; a damaged row must not poison a fit).
std::optional<Correction> fitCorrection(const std::vector<TapePair>& pairs);

/// One taped measurement of one garment, as the catalog keeps it.
struct TapeRecord {
  std::string type;  // garment type at taping time: top | dress | skirt | pants
  std::string name;  // measurement name (drafts::garmentMeasurementNames(type))
  double measuredCm = 0;
  double tapeCm = 0;
};

using CorrectionKey = std::pair<std::string, std::string>;  // (type, measurement)

/// Every (type, measurement) with its pair count and, with enough pairs, its correction.
struct CorrectionTable {
  std::map<CorrectionKey, int> pairs;
  std::map<CorrectionKey, Correction> corrections;
};

CorrectionTable fitCorrections(const std::vector<TapeRecord>& records);

/// API/listing form: [{type, measurement, n, kind ("none" below 3 pairs, with `needs`; "none" with
/// `reason` "no_gain" (leave-one-out no better than raw) or "not_significant" and the figures
/// below when the correction would not help), offset_cm,
/// scale, residual_cm (LOO mean), residual_max_cm, raw_error_cm}], sorted by type then
/// measurement.
nlohmann::json correctionTableJson(const CorrectionTable& table);

/// Applies the corrections of `type` to `measurements` (cm, in place) and records them in the
/// result.json `result`: `measurements` gets the corrected values, `corrections` per corrected
/// measurement {kind, offset_cm, scale, n, residual_cm, raw_cm}. Corrections that do not help
/// (Correction::helps) are not applied. Only measurements present are
/// corrected (a correction never adds one); a corrected value that is not positive is left raw
/// and a warning names it. Returns the names corrected.
std::vector<std::string> applyCorrections(const CorrectionTable& table, const std::string& type,
                                          std::map<std::string, double>& measurements,
                                          nlohmann::json& result);

/// The uncorrected value of `name` in a result.json: corrections[name].raw_cm when the result
/// was corrected, else measurements[name]; nullopt when the capture did not measure it.
std::optional<double> rawMeasurement(const nlohmann::json& result, const std::string& name);

}  // namespace garmcap::pipeline
