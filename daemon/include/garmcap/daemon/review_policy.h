#pragma once
// Which of a capture's warnings need a person before the item is sold, and so whether a new item
// waits for review. The pipeline says both what may be wrong ("the garment is close to the
// screen's colour ..., check it") and how it read something it could read ("bust_circ: sleeves
// cover the sides at the bust; read from the sides down to 6 cm lower"); only the first kind
// holds an item back. Items keep every warning; the API gives the checks apart (Item::toJson).

#include <string>
#include <string_view>
#include <vector>

namespace garmcap::daemon {

/// Whether `warning` is a note: it says how a reading was made, what the station's form cannot
/// show, or what a draft or size run had to assume, not that the item may be wrong.
bool isNote(std::string_view warning);

/// The warnings that are not notes, in their order.
std::vector<std::string> checksOf(const std::vector<std::string>& warnings);

/// Whether a new item waits for review: its type's confidence is under `reviewBelowConfidence`
/// or one of its warnings is a check.
bool needsReview(double confidence, double reviewBelowConfidence,
                 const std::vector<std::string>& warnings);

}  // namespace garmcap::daemon
