// The station's garment vocabulary against a rig written by an independent generator (Blender's
// cloth solver, capture/sim/physical/): its truth.json names what a type is measured by, and the
// station must report exactly those names for the rig to score it.

#include "garmcap/drafts/garment_vocabulary.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "garmcap/drafts/file_io.h"

namespace garmcap::drafts {
namespace {

TEST(GarmentVocabulary, NamesThePhysicalRigsTruthMeasurements) {
  const std::filesystem::path rig = std::filesystem::path(GARMCAP_TEST_DATA_DIR) / "rig_physical";
  const nlohmann::json index = readJsonFile(rig / "rig.json");
  std::set<std::string> typesSeen;
  for (const auto& c : index.at("cases")) {
    const nlohmann::json truth = readJsonFile(rig / c.at("dir").get<std::string>() / "truth.json");
    const std::string type = truth.at("type");
    typesSeen.insert(type);
    std::set<std::string> truthNames;
    for (const auto& [name, value] : truth.at("measurements").items())
      truthNames.insert(name);
    const auto& ours = garmentMeasurementNames(type);
    EXPECT_EQ(std::set<std::string>(ours.begin(), ours.end()), truthNames)
        << c.at("dir").get<std::string>();
    EXPECT_EQ(std::set<std::string>(ours.begin(), ours.end()).size(), ours.size()) << type;
  }
  const auto& types = garmentTypeNames();
  EXPECT_EQ(typesSeen, std::set<std::string>(types.begin(), types.end()));
}

TEST(GarmentVocabulary, AnUnknownTypeIsNamedInTheError) {
  try {
    garmentMeasurementNames("coat");
    FAIL() << "no exception for an unknown type";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("unknown garment type 'coat'"));
  }
}

}  // namespace
}  // namespace garmcap::drafts
