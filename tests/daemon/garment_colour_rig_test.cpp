// Prints called prints on rigs with ground truth: every case of the bundled simulator rig
// (tests/data/rig, the fabric in scene.json) and of the physical rig (tests/data/rig_physical,
// Blender cloth rendered by Cycles: an independent renderer, the fabric in truth.json) runs through
// the pipeline and is named as the station names it (captureColours on the capture's cut-out).
// A print, stripes or checks must read "print", a plain fabric "solid" and one colour whatever
// its shading and folds. Label "rig".
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

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
  std::optional<cv::Vec3b> baseBgr;  // the cloth's own colour, where the truth gives it
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
    std::optional<cv::Vec3b> base;
    if (c.truth.contains("fabric") && c.truth.at("fabric").contains("base_srgb")) {
      const auto rgb = c.truth.at("fabric").at("base_srgb").get<std::vector<double>>();
      base = cv::Vec3b(cv::saturate_cast<uchar>(rgb.at(2) * 255),
                       cv::saturate_cast<uchar>(rgb.at(1) * 255),
                       cv::saturate_cast<uchar>(rgb.at(0) * 255));
    }
    out.push_back({c.id, fabric, isPatterned(fabric), base, *colours});
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

// The palette name nearest a colour by plain CIE76 (OpenCV's Lab, lightness at full weight): the
// name a shopper would give the cloth itself, unlit.
std::string nearestName(const cv::Vec3b& bgr) {
  const auto lab = [](const cv::Vec3b& c) {
    cv::Mat3f px(1, 1, cv::Vec3f(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f));
    cv::cvtColor(px, px, cv::COLOR_BGR2Lab);
    return px(0, 0);
  };
  std::string best;
  double bestD = 1e30;
  for (const auto& name : colourPaletteNames()) {
    const double d = cv::norm(lab(bgr) - lab(paletteColourBgr(name)));
    if (d < bestD) {
      bestD = d;
      best = name;
    }
  }
  return best;
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
  // One cloth is one colour: its lit and shaded sides (Blue and Navy, Purple and Navy, Cream and
  // Beige before the shading was merged) do not list as two.
  // And that one colour is the cloth's own: the name nearest its unlit colour in the truth. At
  // 7af7ea9 (before shading was merged) the first name was it for 11 of the 17 solids, now 16
  // (case_012, a light yellow, reads Beige where Cream is nearest).
  int plain = 0, named = 0;
  for (const auto& r : readings) {
    if (r.patterned || !r.baseBgr)
      continue;
    EXPECT_EQ(r.colours.colours.size(), 1u)
        << r.id << " (" << r.fabric << ") is plain cloth but reads " << r.colours.label();
    ++plain;
    const std::string truth = nearestName(*r.baseBgr);
    if (!r.colours.colours.empty() && r.colours.colours[0].name == truth)
      ++named;
    else
      std::printf("%s: reads %s, the cloth is nearest %s\n", r.id.c_str(),
                  r.colours.label().c_str(), truth.c_str());
  }
  EXPECT_GE(named, plain - 2) << named << " of " << plain << " plain cloths named as their colour";
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
