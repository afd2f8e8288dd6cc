// GarmentCode JSON read back as GarmentCode reads it (garmentcode_rebuild.h), for every type
// drafted at several sizes. Graded sizes: tests/dsw/graded_garmentcode_test.cpp.
#include "garmcap/drafts/export_garmentcode.h"

#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmentcode_rebuild.h"

namespace garmcap::drafts {
namespace {

using nlohmann::json;

void checkType(const std::string& type, const std::string& size,
               const std::map<std::string, double>& design = {}) {
  SCOPED_TRACE(type + " size " + size);
  const Pattern pat = draftGarment(type, sizeChart("korean_women").body(size), design);
  rebuild::checkSpec(pat, json::parse(garmentCodeJson(pat, {"T-1", size})));
}

TEST(GarmentCodeRebuild, EveryTypeWithinAMillimetre) {
  for (const auto& t : garmentTypes())
    for (const char* size : {"44", "66", "88"})
      checkType(t.name, size);
}

TEST(GarmentCodeRebuild, CapAndShortSleevesWithinAMillimetre) {
  // A cap sleeve (8 cm, sewn to the upper armhole only) and a short sleeve (22 cm).
  for (const char* type : {"dress", "blouse", "sweater"})
    for (const double cm : {8.0, 22.0})
      checkType(type, "66",
                {{"sleeve_length",
                  cm / sizeChart("korean_women").body("66").get("arm_shoulder_tip_to_wrist")}});
}

TEST(GarmentCodeRebuild, HLineSkirtClosesIntoATube) {
  const Pattern pat = draftGarment("skirt_h", sizeChart("korean_women").body("55"));
  const json spec = json::parse(garmentCodeJson(pat, {"T-1", "55"}));
  // Pairs of pieces that are sewn: back halves to each other (centre back) and each back half
  // to the unfolded front (side seams).
  std::set<std::pair<std::string, std::string>> joined;
  for (const auto& st : spec["pattern"]["stitches"]) {
    std::string a = st[0]["panel"], b = st[1]["panel"];
    if (a != b)
      joined.insert(std::minmax(a, b));
  }
  const std::set<std::pair<std::string, std::string>> tube = {
      {"skirt_back", "skirt_back_mirrored"},
      {"skirt_back", "skirt_front"},
      {"skirt_back_mirrored", "skirt_front"}};
  EXPECT_EQ(joined, tube);
}

TEST(GarmentCodeRebuild, RefusesAFoldWithoutAStraightCentreLine) {
  Pattern pat = draftGarment("skirt_h", sizeChart("korean_women").body("55"));
  for (auto& p : pat.panels)
    if (p.name == "skirt_front")
      for (auto& q : p.outline)
        q.x() += 0.01 * q.y();  // shear: no vertical edge any more
  EXPECT_THROW(garmentCodeJson(pat, {"T-1", "55"}), GarmentCodeExportError);
}

}  // namespace
}  // namespace garmcap::drafts
