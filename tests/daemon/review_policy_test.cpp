// Which warnings hold an item back (daemon/src/review_policy.cpp). The sentences are the
// pipeline's, as the physical rigs' result.json files give them.
#include "garmcap/daemon/review_policy.h"

#include <gtest/gtest.h>

namespace garmcap::daemon {
namespace {

const std::vector<std::string> kNotes = {
    "bust_circ: sleeves cover the sides at the bust; read from the sides down to 6 cm lower, "
    "where they show",
    "the garment shows a dark slit down from the crotch for 16 cm, taken for the gap between the "
    "legs (legs that touch, or the gap's top in shadow)",
    "inseam: the legs touch below the crotch; the crotch is where the gap between them, followed "
    "up, closes",
    "type: the silhouette is closest to skirt, but it parts into two legs; taken for pants",
    "re-registered a camera shift of 3.2 px",
    "sleeve_length: the form has no arms",
    "draft: ease_bust 6.8 is outside the blouse recipe's range [8.0, 40.0]; drafted with 8.0",
    "size run: 88: the pattern cannot be graded that far",
    "colour not named: the cut-out has no opaque pixel",
};

const std::vector<std::string> kChecks = {
    "the garment is close to the screen's colour (5 cm2 of it over the form keys as screen); its "
    "outline was found against the bare-form frame, check it",
    "waist_circ: the garment does not cover the form at 108 cm",
    "the garment does not cover the centre front at the waist",
    "bust_circ: sleeves cover the garment's sides at 121 cm and below; not measured",
    "no pattern: recipe 'dress_shift': skirt_length = 25.2 cm ends above the hip",
    "size run not graded: the chart has no size",
    "no size guide: the garment has no bust, waist or hip to size it by",
    "hem_circ: the form's hip (80.3 cm) is outside the frame (below its bottom edge); not measured",
};

TEST(ReviewPolicy, NotesSayHowAReadingWasMadeChecksThatTheItemMayBeWrong) {
  for (const auto& w : kNotes)
    EXPECT_TRUE(isNote(w)) << w;
  for (const auto& w : kChecks)
    EXPECT_FALSE(isNote(w)) << w;
}

TEST(ReviewPolicy, AnItemWaitsForReviewOnLowConfidenceOrAnyCheck) {
  EXPECT_FALSE(needsReview(0.9, 0.6, {}));
  EXPECT_FALSE(needsReview(0.9, 0.6, kNotes));
  EXPECT_TRUE(needsReview(0.5, 0.6, {}));
  auto mixed = kNotes;
  mixed.push_back(kChecks.front());
  EXPECT_TRUE(needsReview(0.9, 0.6, mixed));
  EXPECT_EQ(checksOf(mixed), std::vector<std::string>{kChecks.front()});
  EXPECT_TRUE(checksOf(kNotes).empty());
  EXPECT_EQ(checksOf(kChecks), kChecks);  // in their order
}

}  // namespace
}  // namespace garmcap::daemon
