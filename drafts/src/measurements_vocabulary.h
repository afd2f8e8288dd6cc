#pragma once
// Private: the Valentina known-measurement table (measurements_vocabulary.cpp).

#include <string>
#include <vector>

namespace garmcap::drafts::detail {

struct KnownMeasurement {
  const char* code;         // Valentina code, e.g. "G04"
  const char* name;         // e.g. "bust_circ"
  const char* fullName;     // e.g. "Bust circumference"
  const char* description;  // how it is taken
};

/// All 244 known measurements of Valentina 0.7.52, in code order.
const std::vector<KnownMeasurement>& valentinaKnownMeasurements();

}  // namespace garmcap::drafts::detail
