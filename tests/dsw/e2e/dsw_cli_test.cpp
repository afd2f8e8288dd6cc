// End-to-end: the `garmcap coords`, `grade` and `sizerun` commands as a user runs them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../../common/temp_folder.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int status = 0;
  std::string out;
};

Result run(const std::string& args) {
  const std::string cmd = std::string(GARMCAP_BIN_DIR) + "/garmcap " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr)
    r.out += buf;
  r.status = pclose(pipe);
  return r;
}

// One folder for the binary's files, removed when it exits.
fs::path tempDir() {
  static const garmcap::testing::TempFolder folder("garmcap_dsw_cli");
  return folder.path();
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

TEST(DswCli, CoordsPrintsWeightsAndRefusesBadFiles) {
  const fs::path d = tempDir();
  write(d / "poly.json", R"({"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]})");
  write(d / "pts.json", R"({"points": [[2, 2], [4, 1], [0, 0]]})");
  for (const std::string method : {"mvc", "wachspress", "tbc", "green"}) {
    Result r = run("coords --method " + method + " --polygon " + (d / "poly.json").string() +
                   " --points " + (d / "pts.json").string());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.at("weights").size(), 3u) << method;
    EXPECT_EQ(j.contains("edge_weights"), method == "green");
    // The centre: 1/4 each, except tbc, where it lies on the diagonal of two triangles;
    // every method reproduces it.
    const auto& w0 = j["weights"][0];
    EXPECT_NEAR(4 * (w0[1].get<double>() + w0[2].get<double>()), 2.0, 1e-12) << method;
    EXPECT_NEAR(4 * (w0[2].get<double>() + w0[3].get<double>()), 2.0, 1e-12) << method;
    if (method != "tbc") {
      EXPECT_NEAR(w0[0].get<double>(), 0.25, 1e-12) << method;
    }
    if (method != "green") {
      EXPECT_NEAR(j["weights"][1][1].get<double>(), 0.75, 1e-12) << method;
      EXPECT_EQ(j["weights"][2][0].get<double>(), 1.0) << method;
    }
  }
  write(d / "bad.json", R"({"polygon": [[0, 0], [4, 0]], "extra": 1})");
  Result bad = run("coords --polygon " + (d / "bad.json").string() + " --points " +
                   (d / "pts.json").string());
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.out.find("bad.json"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("extra"), std::string::npos) << bad.out;
  write(d / "flat.json", R"({"polygon": [[0, 0], [1, 1], [2, 2]]})");
  Result flat = run("coords --polygon " + (d / "flat.json").string() + " --points " +
                    (d / "pts.json").string());
  EXPECT_NE(flat.status, 0);
  EXPECT_NE(flat.out.find("zero area"), std::string::npos) << flat.out;
  Result method = run("coords --method foo --polygon " + (d / "poly.json").string() + " --points " +
                      (d / "pts.json").string());
  EXPECT_NE(method.status, 0);
  EXPECT_NE(method.out.find("foo"), std::string::npos) << method.out;
}

// The hem of one panel read from a pattern file, found by geometry alone: the chain of outline
// edges through the lowest vertex that turns less than 45 degrees at each vertex (a hem meets
// the side seam and the centre line at a corner). Shares nothing with drafts' edge roles.
double hemChainLength(const nlohmann::json& panel) {
  std::vector<std::pair<double, double>> o;
  for (const auto& v : panel.at("outline"))
    o.emplace_back(v.at(0).get<double>(), v.at(1).get<double>());
  const int n = static_cast<int>(o.size());
  auto at = [&](int i) { return o[static_cast<std::size_t>(((i % n) + n) % n)]; };
  auto dist = [](std::pair<double, double> a, std::pair<double, double> b) {
    return std::hypot(b.first - a.first, b.second - a.second);
  };
  auto straightOn = [&](int v) {  // turn at vertex v under 45 degrees
    const auto a = at(v - 1), b = at(v), c = at(v + 1);
    const double ux = b.first - a.first, uy = b.second - a.second;
    const double wx = c.first - b.first, wy = c.second - b.second;
    return (ux * wx + uy * wy) > std::cos(M_PI / 4) * std::hypot(ux, uy) * std::hypot(wx, wy);
  };
  int low = 0;
  for (int i = 1; i < n; ++i)
    if (o[static_cast<std::size_t>(i)].second > o[static_cast<std::size_t>(low)].second)
      low = i;
  // The hem edge at the lowest vertex is the flatter of its two edges (the other is a side or
  // the centre line); from there the chain runs on through every vertex it passes straight on.
  auto slope = [&](int a) {
    const auto p = at(a), q = at(a + 1);
    return std::abs(q.second - p.second) / std::max(dist(p, q), 1e-12);
  };
  const int first = slope(low) <= slope(low - 1) ? low : low - 1;
  double len = dist(at(first), at(first + 1));
  int edges = 1;
  for (int v = first + 1; edges < n && straightOn(v); ++v, ++edges)
    len += dist(at(v), at(v + 1));
  for (int v = first; edges < n && straightOn(v); --v, ++edges)
    len += dist(at(v - 1), at(v));
  return len;
}

TEST(DswCli, GradeAndSizeRunWriteTheirFiles) {
  const fs::path d = tempDir();
  const std::string data = GARMCAP_TEST_DATA_DIR;
  Result g = run("grade --pattern " + data + "/designs/dress_55.json --to " + data +
                 "/bodies/table4_2_77.json --dart-compensation --out " + (d / "g77.json").string() +
                 " --svg " + (d / "g77.svg").string());
  ASSERT_EQ(g.status, 0) << g.out;
  EXPECT_TRUE(fs::exists(d / "g77.json"));
  EXPECT_TRUE(fs::exists(d / "g77.svg"));
  Result m = run("measure --pattern " + (d / "g77.json").string());
  ASSERT_EQ(m.status, 0) << m.out;
  // Dart compensation keeps the source's own waist ease (65 + 6 at size 55): 75 + 6 at 77.
  EXPECT_NEAR(nlohmann::json::parse(m.out)["measurements"]["waist_circ"].get<double>(), 81.0, 0.05);
  // --margin sets another ease on purpose: 75 + 3.
  Result g3 = run("grade --pattern " + data + "/designs/dress_55.json --to " + data +
                  "/bodies/table4_2_77.json --dart-compensation --margin 3 --out " +
                  (d / "g77m3.json").string());
  ASSERT_EQ(g3.status, 0) << g3.out;
  Result m3 = run("measure --pattern " + (d / "g77m3.json").string());
  ASSERT_EQ(m3.status, 0) << m3.out;
  EXPECT_NEAR(nlohmann::json::parse(m3.out)["measurements"]["waist_circ"].get<double>(), 78.0,
              0.05);
  Result s = run("sizerun --pattern " + data +
                 "/designs/dress_55.json --chart korean_women --out " + (d / "run").string());
  ASSERT_EQ(s.status, 0) << s.out;
  EXPECT_TRUE(fs::exists(d / "run" / "size_guide.json"));
  EXPECT_TRUE(fs::exists(d / "run" / "size_guide.csv"));
  EXPECT_TRUE(fs::exists(d / "run" / "dress_88.json"));
  Result both = run("grade --pattern " + data +
                    "/designs/dress_55.json --to x.json --size 55 --chart korean_women --out " +
                    (d / "x.json").string());
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.out.find("either --to"), std::string::npos) << both.out;
  fs::remove_all(d);
}

// Issue 18: the size guide of the flared dress read its hem at the un-flared draft corners
// (94.5 cm for a 126 cm hem). Every row of the guide must be the hem of that size's pattern file,
// measured along the skirt panels' hem edges there (times the pieces cut).
TEST(DswCli, SizeRunGuideHemIsTheFlaredHemOfEverySize) {
  const fs::path d = tempDir() / "hem";
  const std::string data = GARMCAP_TEST_DATA_DIR;
  Result s = run("sizerun --pattern " + data +
                 "/designs/dress_55.json --chart korean_women --out " + d.string());
  ASSERT_EQ(s.status, 0) << s.out;
  std::ifstream guideIn(d / "size_guide.json");
  const nlohmann::json guide = nlohmann::json::parse(guideIn);
  ASSERT_EQ(guide.at("rows").size(), 5u);
  for (const auto& row : guide.at("rows")) {
    const std::string size = row.at("size");
    std::ifstream in(d / ("dress_" + size + ".json"));
    const nlohmann::json pattern = nlohmann::json::parse(in);
    double hem = 0;
    int skirts = 0;
    for (const auto& panel : pattern.at("panels")) {
      if (panel.at("name").get<std::string>().rfind("skirt_", 0) != 0)
        continue;
      const int pieces =
          panel.at("cut_count").get<int>() * (panel.at("cut_on_fold").get<bool>() ? 2 : 1);
      hem += hemChainLength(panel) * pieces;
      ++skirts;
    }
    ASSERT_EQ(skirts, 2) << size;
    EXPECT_NEAR(row.at("garment").at("hem_circ").get<double>(), hem, 0.5) << "size " << size;
    if (size == guide.at("base_size")) {
      EXPECT_GT(hem, 120.0) << "the design flares the hem 8 cm per side seam edge";
    }
  }
  fs::remove_all(d);
}

}  // namespace
