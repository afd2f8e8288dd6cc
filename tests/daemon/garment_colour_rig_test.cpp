// Prints called prints on rigs with ground truth: every case of the bundled simulator rig
// (tests/data/rig, the fabric in scene.json) and of the physical rig (tests/data/rig_physical,
// Blender cloth rendered by Cycles: an independent renderer, the fabric in truth.json) runs through
// the pipeline and is named as the station names it (captureColours on the capture's cut-out).
// A print, stripes or checks must read "print", a plain fabric "solid" whatever its shading and
// folds. Label "rig".
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "garmcap/capture/rig.h"
#include "garmcap/daemon/garment_colour.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::daemon {
namespace {

namespace fs = std::filesystem;

struct Reading {
  std::string id;
  std::string fabric;  // the truth's name for the fabric
  bool patterned = false;
  GarmentColours colours;
};

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  if (!in)
    throw std::runtime_error(p.string() + ": cannot open");
  return nlohmann::json::parse(in);
}

// The fabric the case was made with: the simulator's scene.json, else the physical rig's
// truth.json ("light", "mid", "dark", "form" are plain cloth of those colours).
std::string fabricOf(const capture::RigCase& c) {
  if (fs::exists(c.dir / "scene.json"))
    return readJson(c.dir / "scene.json").at("fabric").at("kind").get<std::string>();
  return c.truth.at("fabric").at("kind").get<std::string>();
}

bool isPatterned(const std::string& fabric) {
  if (fabric == "print" || fabric == "stripes" || fabric == "checks")
    return true;
  if (fabric == "solid" || fabric == "light" || fabric == "mid" || fabric == "dark" ||
      fabric == "form")
    return false;
  throw std::runtime_error("unknown fabric kind in the truth: " + fabric);
}

std::vector<Reading> readRig(const fs::path& rigDir) {
  pipeline::CaptureOptions options;
  options.makeTexture = false;  // the cut-out is what the station names
  std::vector<Reading> out;
  for (const auto& info : capture::readRig(rigDir).cases) {
    const auto c = capture::loadRigCase(info.dir);
    const auto r = pipeline::runCapture(c.empty, c.dressed, c.calibration, options);
    const auto colours = captureColours(r, c.dressed);
    if (!colours) {
      ADD_FAILURE() << c.id << ": the capture has no cut-out to name";
      continue;
    }
    const std::string fabric = fabricOf(c);
    out.push_back({c.id, fabric, isPatterned(fabric), *colours});
    std::printf("%s %-8s %-16s print share %.3f -> %s\n", c.id.c_str(), fabric.c_str(),
                colours->label().c_str(), colours->printShare,
                colours->printed ? "print" : "solid");
  }
  return out;
}

void expectTruth(const std::vector<Reading>& readings) {
  for (const auto& r : readings)
    EXPECT_EQ(r.colours.printed, r.patterned)
        << r.id << " (" << r.fabric << ", " << r.colours.label() << ") has print share "
        << r.colours.printShare;
}

const fs::path kData = GARMCAP_TEST_DATA_DIR;

TEST(GarmentColourRig, BundledRigPrintsArePrintsAndSolidsSolid) {
  const auto readings = readRig(kData / "rig");
  ASSERT_EQ(readings.size(), 6u);
  expectTruth(readings);
  // The case: the navy skirt with light-blue dots (case_002) used to read "solid".
  const auto skirt = std::find_if(readings.begin(), readings.end(),
                                  [](const Reading& r) { return r.id == "case_002"; });
  ASSERT_NE(skirt, readings.end());
  EXPECT_TRUE(skirt->colours.printed);
  ASSERT_FALSE(skirt->colours.colours.empty());
  EXPECT_EQ(skirt->colours.colours[0].name, "Navy");
}

TEST(GarmentColourRig, PhysicalRigPrintsArePrintsAndSolidsSolid) {
  const auto readings = readRig(kData / "rig_physical");
  ASSERT_EQ(readings.size(), 24u);
  int solids = 0;
  for (const auto& r : readings)
    solids += !r.patterned;
  EXPECT_GE(solids, 10) << "the physical rig's plain fabrics are the check on shading and folds";
  expectTruth(readings);
}

// Any other rig with its truth, e.g. fresh simulator scenes no setting was chosen on:
//   garmcap rig make --count 24 --seed 91761 --width 864 --height 1152 --image-format jpg --out R
//   GARMCAP_COLOUR_RIG=R daemon_colour_rig_tests --gtest_filter='*OtherRig*'
TEST(GarmentColourRig, OtherRigFromTheEnvironment) {
  const char* dir = std::getenv("GARMCAP_COLOUR_RIG");
  if (dir == nullptr || *dir == '\0')
    GTEST_SKIP() << "set GARMCAP_COLOUR_RIG to a rig folder";
  const auto readings = readRig(dir);
  ASSERT_FALSE(readings.empty());
  expectTruth(readings);
}

}  // namespace
}  // namespace garmcap::daemon
