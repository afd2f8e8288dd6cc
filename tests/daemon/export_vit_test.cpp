// The .vit export (drafts::measurementsToVit, served as /api/items/{id}/measurements.vit) opened
// by Debian's Valentina 0.7.52 headless: Valentina drafts its bundled Keiko skirt example from our
// file. Same values as the example's own keiko.vit must give the same piece geometry; other
// values must change it (so Valentina really read ours).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <vector>

#include "garmcap/drafts/measurements.h"

namespace {

namespace fs = std::filesystem;
const fs::path kExamples = "/usr/share/doc/valentina/examples/collection";

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// Runs Valentina on Keiko_skirt.val with `vit`; returns the path data of the exported SVG.
std::string keikoPaths(const fs::path& dir, const std::string& vit, const std::string& name) {
  fs::create_directories(dir / name);
  std::ofstream(dir / (name + ".vit")) << vit;
  const std::string cmd = "cd '" + dir.string() + "' && HOME='" + dir.string() +
                          "' QT_QPA_PLATFORM=offscreen timeout 120 valentina -b " + name + " -d " +
                          name + " -f 0 --exportOnlyDetails -m " + name +
                          ".vit Keiko_skirt.val > " + name + ".log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / (name + ".log"));
  std::string svg;
  for (const auto& e : fs::directory_iterator(dir / name))
    if (e.path().extension() == ".svg")
      svg += slurp(e.path());
  // The layout may place the pieces in either order: compare the set of piece outlines.
  std::vector<std::string> pieces;
  const std::regex d(" d=\"([^\"]+)\"");
  for (std::sregex_iterator it(svg.begin(), svg.end(), d), end; it != end; ++it)
    pieces.push_back((*it)[1].str());
  std::sort(pieces.begin(), pieces.end());
  std::string paths;
  for (const auto& p : pieces)
    paths += p + "\n";
  return paths;
}

TEST(VitExport, ValentinaDraftsFromOurFile) {
  if (!fs::exists("/usr/bin/valentina") || !fs::exists(kExamples / "Keiko_skirt.val"))
    GTEST_SKIP() << "Debian's valentina is not installed (station.sh deps installs it)";
  const fs::path dir =
      fs::temp_directory_path() / ("garmcap_vit_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(kExamples / "Keiko_skirt.val", dir / "Keiko_skirt.val");
  const std::string reference = keikoPaths(dir, slurp(kExamples / "keiko.vit"), "reference");
  ASSERT_FALSE(reference.empty());

  garmcap::drafts::Measurements m({{"waist_circ", 59.5},
                                   {"hip_circ", 89.0},
                                   {"height_knee", 50.0},
                                   {"height_waist_side_to_hip", 15.0},
                                   {"leg_crotch_to_floor", 79.25}});
  const std::string same = keikoPaths(dir, garmcap::drafts::measurementsToVit(m), "ours");
  EXPECT_EQ(same, reference) << "Valentina drew other geometry from our .vit with the same values";

  m.set("hip_circ", 110.0);
  m.set("waist_circ", 90.0);
  const std::string bigger = keikoPaths(dir, garmcap::drafts::measurementsToVit(m), "bigger");
  EXPECT_FALSE(bigger.empty());
  EXPECT_NE(bigger, reference) << "Valentina ignored the values of our .vit";
  fs::remove_all(dir);
}

}  // namespace
