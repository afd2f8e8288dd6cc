#include "garmcap/daemon/review_policy.h"

#include <algorithm>
#include <array>
#include <iterator>

namespace garmcap::daemon {
namespace {

struct NotePattern {
  std::string_view text;
  bool prefix;  // true: the warning starts with `text`; false: it contains it
};

// The pipeline's and the processor's sentences that are notes (core/garmcap, daemon/src). Of six
// physical rigs' 92 cases (`garmcap rig eval`; docs/api.md, "checks") 79 have a warning, which
// held each for review, and 17 a check: 15 an outline found against the bare frame (a garment
// close to the screen's colour), 2 more a reading not made.
constexpr std::array<NotePattern, 9> kNotes = {{
    // How a reading was made, where it could be made:
    {"read from the sides down to", false},                        // the bust under sleeves
    {"the garment shows a dark slit down from the crotch", true},  // the legs' gap in shadow
    {"inseam: the legs touch below the crotch", true},             // the crotch from the gap's V
    {"but it parts into two legs; taken for pants", false},        // a wide pair's silhouette
    {"re-registered a camera shift of", true},                     // the form found again
    // What the station's form cannot show (a torso form has no arms: always, not this item):
    {": the form has no arms", false},
    // What a draft, a size run or the colour's name had to assume (the item's values stand):
    {"draft: ", true},  // "draft: ease_bust 6.8 is outside the blouse recipe's range ..."
    {"size run: ", true},
    {"colour not named", true},
}};

}  // namespace

bool isNote(std::string_view warning) {
  return std::any_of(kNotes.begin(), kNotes.end(), [&](const NotePattern& n) {
    return n.prefix ? warning.substr(0, n.text.size()) == n.text
                    : warning.find(n.text) != std::string_view::npos;
  });
}

std::vector<std::string> checksOf(const std::vector<std::string>& warnings) {
  std::vector<std::string> out;
  std::copy_if(warnings.begin(), warnings.end(), std::back_inserter(out),
               [](const std::string& w) { return !isNote(w); });
  return out;
}

bool needsReview(double confidence, double reviewBelowConfidence,
                 const std::vector<std::string>& warnings) {
  return confidence < reviewBelowConfidence ||
         std::any_of(warnings.begin(), warnings.end(),
                     [](const std::string& w) { return !isNote(w); });
}

}  // namespace garmcap::daemon
