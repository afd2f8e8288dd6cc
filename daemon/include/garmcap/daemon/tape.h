#pragma once
// The shop's tape measure on the station (issue 15 part 7): staff tape a few garments once, the
// catalog keeps each taped value with the pipeline's uncorrected reading, and every later capture
// (and re-run) is corrected per type and measurement (pipeline/measurement_correction.h): the
// station fits the table when a capture starts and the pipeline applies it before drafting.
//
//   POST   /api/tape         {"item": 12, "measurements": {"bust_circ": 92.5, ...}}  (cm)
//     -> 200 {"item": 12, "tape": [...the item's rows...], "corrections": [...table...]}
//     400 naming the field: unknown item, an item without a type, a name the item's type does not
//     have, a name the capture did not measure, a value that is not a number in (0, 400] cm.
//   GET    /api/tape         -> 200 {"tape": [...all rows...], "corrections": [...table...]}
//   DELETE /api/tape/{item}  -> 200 {"deleted": n, "corrections": [...]}; 404 when it has none
//
// Thread: everything that takes a Catalog runs on the station strand (withCatalog).

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "garmcap/daemon/catalog.h"
#include "garmcap/pipeline/measurement_correction.h"

namespace garmcap::daemon {

/// Largest taped value accepted, cm: no garment measurement of the vocabulary comes near it, and
/// a typo of a decimal point (925 for 92.5) does not pass.
inline constexpr double kMaxTapeCm = 400;

struct TapeRequest {
  std::int64_t itemId = 0;
  std::map<std::string, double> tapeCm;
};

/// The POST body's shape: an object with exactly "item" (positive integer) and "measurements"
/// (1..kMaxTapeNames names of [a-z0-9_], 1..64 bytes, to numbers in (0, kMaxTapeCm]). Throws
/// BadRequest naming the field.
TapeRequest parseTapeRequest(const nlohmann::json& body);

/// The rows to store for a request, checked against the item: it exists and is live, has a type,
/// every name is one of its type's measurements (drafts::garmentMeasurementNames) and was measured
/// by its capture (the uncorrected reading of result.json, else the stored value). Throws
/// BadRequest naming the field.
std::vector<TapeEntry> tapeEntriesFor(Catalog& catalog, const TapeRequest& request);

/// The correction table fitted on every live item's taped measurements.
pipeline::CorrectionTable tapeCorrections(Catalog& catalog);

/// Rows as the API lists them: [{item, type, measurement, tape_cm, measured_cm, created_at}].
nlohmann::json tapeRowsJson(const std::vector<TapeEntry>& rows);

}  // namespace garmcap::daemon
