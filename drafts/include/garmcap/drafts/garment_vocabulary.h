#pragma once
// The garment types a station captures and the measurements each is given (the names of
// result.json, the rigs' truth.json, the tape corrections and the exports). Like fabric_kind.h it
// lives in drafts because drafts is the one library both the pipeline and the scene simulator may
// include; only the names are shared, never how a measurement is taken or drawn
// (docs/measurement_model.md).

#include <string>
#include <vector>

namespace garmcap::drafts {

/// top, dress, skirt, pants.
const std::vector<std::string>& garmentTypeNames();

/// The measurements of a garment type, in the order result.json lists them. Throws
/// std::invalid_argument "unknown garment type '<type>' (expected top, dress, skirt or pants)".
const std::vector<std::string>& garmentMeasurementNames(const std::string& type);

}  // namespace garmcap::drafts
