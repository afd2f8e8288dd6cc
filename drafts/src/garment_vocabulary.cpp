#include "garmcap/drafts/garment_vocabulary.h"

#include <map>
#include <stdexcept>

namespace garmcap::drafts {

const std::vector<std::string>& garmentTypeNames() {
  static const std::vector<std::string> kTypes = {"top", "dress", "skirt", "pants"};
  return kTypes;
}

const std::vector<std::string>& garmentMeasurementNames(const std::string& type) {
  static const std::map<std::string, std::vector<std::string>> kNames = {
      {"top", {"bust_circ", "waist_circ", "hem_circ", "garment_length", "sleeve_length"}},
      {"dress",
       {"bust_circ", "waist_circ", "hip_circ", "hem_circ", "garment_length", "skirt_length",
        "sleeve_length"}},
      {"skirt", {"waist_circ", "hip_circ", "hem_circ", "skirt_length"}},
      {"pants", {"waist_circ", "hip_circ", "outseam", "inseam", "leg_opening_circ"}}};
  const auto it = kNames.find(type);
  if (it == kNames.end())
    throw std::invalid_argument("unknown garment type '" + type +
                                "' (expected top, dress, skirt or pants)");
  return it->second;
}

}  // namespace garmcap::drafts
