// End-to-end: `garmcap render` and `garmcap rig make` as a user runs them (the built binary),
// in particular garments drafted for the sizes of a size chart (--size/--chart, --chart).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "common/garmcap_cli.h"

namespace {

using garmcap::testing::CliResult;
using garmcap::testing::readText;
using garmcap::testing::runGarmcap;
using garmcap::testing::TempDir;

const std::string kForm =
    std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";

nlohmann::json readJson(const std::string& path) {
  return nlohmann::json::parse(readText(path));
}

void expectRefused(const CliResult& r, std::initializer_list<std::string> needles) {
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err.rfind("garmcap: error: ", 0), 0u) << r.err;
  for (const auto& n : needles)
    EXPECT_NE(r.err.find(n), std::string::npos) << "no '" << n << "' in: " << r.err;
}

// The garment measurements of a draft as `garmcap draft` + `garmcap measure` give them.
// The simulator raises a skirt's or trousers' 1 cm waist ease to its minimum of 2.5 cm
// (simDraftDesign in capture/scene.h); `set` adds other design values.
nlohmann::json measuredDraft(const TempDir& d, const std::string& recipe, const std::string& size,
                             const std::string& chart, const std::string& set = "") {
  const std::string p = d / (recipe + "_" + size + ".json");
  const CliResult r = runGarmcap("draft --type " + recipe + " --size " + size + " --chart " +
                                 chart + " --set ease_waist=2.5 " + set + " --out " + p);
  EXPECT_EQ(r.status, 0) << r.err;
  const CliResult m = runGarmcap("measure --pattern " + p);
  EXPECT_EQ(m.status, 0) << m.err;
  return nlohmann::json::parse(m.out).at("measurements");
}

// Every garment type renders for a chart size on the form of that size (`make-form`), its
// truth the draft's measurements (truth.json keeps 0.01 cm, `measure` 0.001 cm).
TEST(RenderCli, EveryTypeDraftedForAChartSize) {
  const TempDir d("render_cli_chart");
  const CliResult made =
      runGarmcap("make-form --chart korean_women --size 66 --out " + (d / "form66.obj"));
  ASSERT_EQ(made.status, 0) << made.err;
  const std::string form = d / "form66.json";
  struct Want {
    std::string type, extra;
  };
  for (const Want& w : {Want{"skirt", "--skirt h_line"}, Want{"dress", "--skirt a_line"},
                        Want{"top", "--sleeve long"}, Want{"pants", ""}}) {
    SCOPED_TRACE(w.type);
    const std::string out = d / ("case_" + w.type);
    const CliResult r = runGarmcap("render --type " + w.type + " " + w.extra +
                                   " --size 66 --chart korean_women --form " + form +
                                   " --seed 3 --width 150 --height 200 --out " + out);
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* f : {"empty.png", "dressed.png", "truth.json", "scene.json"})
      EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + f)) << f;
    const auto scene = readJson(out + "/scene.json");
    EXPECT_EQ(scene.at("drafted_from"),
              nlohmann::json({{"chart", "korean_women"}, {"size", "66"}}));
    const auto truth = readJson(out + "/truth.json");
    EXPECT_EQ(truth.at("type"), w.type);
    EXPECT_NE(r.err.find("drafted with recipe"), std::string::npos) << r.err;
  }
  // The skirt's truth is the H-line skirt draft of size 66, as `garmcap measure` reads it.
  const auto truth = readJson(d / "case_skirt/truth.json").at("measurements");
  const auto draft = measuredDraft(d, "skirt_h", "66", "korean_women");
  for (const char* k : {"waist_circ", "hip_circ", "hem_circ", "skirt_length"})
    EXPECT_NEAR(truth.at(k).get<double>(), draft.at(k).get<double>(), 0.01) << k;
  // The trousers' truth names: outseam, inseam and leg opening are the draft's, with the
  // trousers ending 6 cm above the floor (pants_length = 1 - 6 / waist-to-floor).
  const auto pants = readJson(d / "case_pants/truth.json").at("measurements");
  measuredDraft(d, "pants", "66", "korean_women");
  const double floor =
      readJson(d / "pants_66.json").at("measurements").at("leg_waist_side_to_floor").get<double>();
  const auto trousers = measuredDraft(d, "pants", "66", "korean_women",
                                      "--set pants_length=" + std::to_string(1 - 6 / floor));
  EXPECT_NEAR(pants.at("outseam").get<double>(), trousers.at("outseam_length").get<double>(), 0.01);
  EXPECT_NEAR(pants.at("inseam").get<double>(), trousers.at("inseam_length").get<double>(), 0.01);
  EXPECT_NEAR(pants.at("leg_opening_circ").get<double>(), trousers.at("hem_circ").get<double>(),
              0.01);
}

TEST(RenderCli, BadChartOptionsAreRefused) {
  const TempDir d("render_cli_bad");
  const std::string common =
      "render --type skirt --form " + kForm + " --width 60 --height 80 --out " + (d / "c");
  expectRefused(runGarmcap(common + " --size 66"), {"--chart"});
  expectRefused(runGarmcap(common + " --size 66 --chart martian"), {"martian", "korean_women"});
  expectRefused(runGarmcap(common + " --size 99 --chart korean_women"), {"'99'", "korean_women"});
  expectRefused(runGarmcap(common), {"--measurements", "--size"});
  EXPECT_FALSE(std::filesystem::exists(d / "c"));
}

// --image-format jpg writes empty.jpg and dressed.jpg (the calibration names the JPEG); a bad
// format or quality is refused before anything is written.
TEST(RenderCli, JpegFramesAndTheirOptions) {
  const TempDir d("render_cli_jpeg");
  const std::string common = "render --type skirt --size 46 --chart french_women --form " + kForm +
                             " --seed 2 --width 120 --height 160 --out ";
  const std::string out = d / "jpg";
  const CliResult r = runGarmcap(common + out + " --image-format jpg --jpeg-quality 90");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"empty.jpg", "dressed.jpg", "truth.json", "calibration.json"})
    EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + f)) << f;
  EXPECT_FALSE(std::filesystem::exists(out + "/empty.png"));
  EXPECT_EQ(readJson(out + "/calibration.json").at("empty_frame"), "empty.jpg");
  // The same case rendered again as PNG replaces the JPEGs.
  ASSERT_EQ(runGarmcap(common + out).status, 0);
  EXPECT_TRUE(std::filesystem::is_regular_file(out + "/empty.png"));
  EXPECT_FALSE(std::filesystem::exists(out + "/empty.jpg"));
  EXPECT_FALSE(std::filesystem::exists(out + "/dressed.jpg"));

  const std::string bad = d / "bad";
  expectRefused(runGarmcap(common + bad + " --image-format jpg --jpeg-quality 0"),
                {"--jpeg-quality", "1..100", "0"});
  expectRefused(runGarmcap(common + bad + " --image-format jpg --jpeg-quality 101"),
                {"--jpeg-quality", "1..100", "101"});
  expectRefused(runGarmcap(common + bad + " --image-format gif"), {"--image-format", "gif"});
  expectRefused(runGarmcap(common + bad + " --jpeg-quality 90"),
                {"--jpeg-quality", "--image-format jpg"});
  EXPECT_FALSE(std::filesystem::exists(bad));
}

// rig.json records how the frames are stored.
TEST(RigMakeCli, RecordsItsImageFormat) {
  const TempDir d("rig_cli_jpeg");
  const std::string common =
      "rig make --count 2 --seed 5 --width 120 --height 160 --form " + kForm + " --out ";
  const std::string jpg = d / "jpg";
  ASSERT_EQ(runGarmcap(common + jpg + " --image-format jpg").status, 0);
  const auto index = readJson(jpg + "/rig.json");
  EXPECT_EQ(index.at("image_format"), "jpg");
  EXPECT_EQ(index.at("jpeg_quality"), 92);
  for (const auto& c : index.at("cases")) {
    const std::string dir = jpg + "/" + c.at("dir").get<std::string>();
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/empty.jpg")) << dir;
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/dressed.jpg")) << dir;
    EXPECT_FALSE(std::filesystem::exists(dir + "/empty.png")) << dir;
  }
  const std::string png = d / "png";
  ASSERT_EQ(runGarmcap(common + png).status, 0);
  const auto pngIndex = readJson(png + "/rig.json");
  EXPECT_EQ(pngIndex.at("image_format"), "png");
  EXPECT_FALSE(pngIndex.contains("jpeg_quality"));
  EXPECT_TRUE(std::filesystem::is_regular_file(png + "/case_000/empty.png"));
  expectRefused(runGarmcap(common + (d / "bad") + " --image-format jpg --jpeg-quality 200"),
                {"--jpeg-quality", "1..100"});
  EXPECT_FALSE(std::filesystem::exists(d / "bad"));
}

// `rig make --chart`: every case a size of the chart, the form made for that size and the
// garment drafted for it, recorded in rig.json and scene.json; the same rig without the chart
// samples ease on the given form instead.
TEST(RigMakeCli, ChartDraftsEveryGarmentForAChartSize) {
  const TempDir d("rig_cli_chart");
  const std::string rig = d / "rig";
  const CliResult r = runGarmcap("rig make --count 4 --seed 5 --width 120 --height 160 --form " +
                                 kForm + " --chart french_women --out " + rig);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto index = readJson(rig + "/rig.json");
  EXPECT_EQ(index.at("chart"), "french_women");
  const std::vector<std::string> sizes = {"34", "36", "38", "40", "42", "44", "46", "48"};
  ASSERT_EQ(index.at("cases").size(), 4u);
  for (const auto& c : index.at("cases")) {
    const std::string size = c.at("size");
    EXPECT_NE(std::find(sizes.begin(), sizes.end(), size), sizes.end()) << size;
    const auto scene = readJson(rig + "/" + c.at("dir").get<std::string>() + "/scene.json");
    EXPECT_EQ(scene.at("drafted_from").at("size"), size);
    const std::string form = scene.at("form");
    EXPECT_NE(form.find("forms/french_women_" + size + "/form.json"), std::string::npos) << form;
    EXPECT_TRUE(std::filesystem::is_regular_file(form)) << form;
    if (c.at("type") == "skirt") {
      const std::string recipe = c.at("attributes").at("skirt") == "a_line" ? "skirt_a" : "skirt_h";
      const auto truth = readJson(rig + "/" + c.at("dir").get<std::string>() + "/truth.json");
      const auto draft = measuredDraft(d, recipe, size, "french_women");
      EXPECT_NEAR(truth.at("measurements").at("hip_circ").get<double>(),
                  draft.at("hip_circ").get<double>(), 0.01);
    }
  }
  const std::string plain = d / "plain";
  ASSERT_EQ(runGarmcap("rig make --count 1 --seed 5 --width 120 --height 160 --form " + kForm +
                       " --out " + plain)
                .status,
            0);
  const auto plainIndex = readJson(plain + "/rig.json");
  EXPECT_FALSE(plainIndex.contains("chart"));
  EXPECT_FALSE(plainIndex.at("cases")[0].contains("size"));
  EXPECT_FALSE(std::filesystem::exists(plain + "/forms"));
}

TEST(RigMakeCli, UnknownChartIsRefused) {
  const TempDir d("rig_cli_bad");
  expectRefused(runGarmcap("rig make --count 1 --seed 1 --width 60 --height 80 --form " + kForm +
                           " --chart martian --out " + (d / "rig")),
                {"martian", "korean_women"});
}

}  // namespace

namespace {

// The first bytes of a file (its format's signature).
std::string head(const std::string& path, std::size_t n) {
  return readText(path).substr(0, n);
}

}  // namespace

// `garmcap capture --out` writes a capture's images as the station stores them
// (pipeline/image_files.h): the shop photos as JPEG and as WebP, the rest as PNG. The WebP is
// read back by libwebp's own `dwebp`, not by OpenCV, which wrote it.
TEST(CaptureCli, WritesThePhotosAsTheStationStoresThem) {
  const TempDir d("capture_cli_photos");
  const std::string scene = d / "scene";
  const CliResult made = runGarmcap("render --type skirt --size 46 --chart french_women --form " +
                                    kForm + " --seed 5 --width 480 --height 640 --out " + scene);
  ASSERT_EQ(made.status, 0) << made.err;
  const std::string out = d / "out";
  const CliResult r =
      runGarmcap("capture --empty " + scene + "/empty.png --dressed " + scene +
                 "/dressed.png --calibration " + scene + "/calibration.json --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(head(out + "/product.jpg", 3), "\xff\xd8\xff");
  EXPECT_EQ(head(out + "/product_4x5.jpg", 3), "\xff\xd8\xff");
  for (const char* png : {"cutout.png", "silhouette.png", "overlay.png"})
    EXPECT_EQ(head(out + "/" + png, 8), "\x89PNG\r\n\x1a\n") << png;
  for (const char* webp : {"product.webp", "product_4x5.webp"}) {
    const std::string path = out + "/" + webp;
    ASSERT_TRUE(std::filesystem::is_regular_file(path)) << webp << " missing";
    EXPECT_EQ(head(path, 4), "RIFF") << webp;
    const int st = std::system(("dwebp -quiet '" + path + "' -o '" + path + ".ppm'").c_str());
    EXPECT_EQ(st, 0) << "dwebp cannot read " << webp;
  }
  EXPECT_FALSE(std::filesystem::exists(out + "/product_webp.webp"));
}

// `garmcap capture --back`: a second shot of the same garment adds the back photos and the
// ghost-mannequin front (here the dressed frame again stands for the back: the same garment, so
// it is taken); a back shot of the bare form is refused by name and nothing is written.
TEST(CaptureCli, BackShotAddsTheBackAndGhostPhotosOrIsRefused) {
  const TempDir d("capture_cli_back");
  const std::string scene = d / "scene";
  const CliResult made = runGarmcap("render --type top --size 66 --chart korean_women --form " +
                                    kForm + " --seed 3 --width 480 --height 640 --out " + scene);
  ASSERT_EQ(made.status, 0) << made.err;
  const std::string common = "capture --empty " + scene + "/empty.png --dressed " + scene +
                             "/dressed.png --calibration " + scene + "/calibration.json";
  const std::string out = d / "out";
  const CliResult r = runGarmcap(common + " --back " + scene + "/dressed.png --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* jpg :
       {"product_back.jpg", "product_back_4x5.jpg", "product_ghost.jpg", "product_ghost_4x5.jpg"})
    EXPECT_EQ(head(out + "/" + jpg, 3), "\xff\xd8\xff") << jpg;
  EXPECT_EQ(head(out + "/cutout_back.png", 8), "\x89PNG\r\n\x1a\n");
  const auto result = nlohmann::json::parse(readText(out + "/result.json"));
  ASSERT_TRUE(result.contains("back_shot")) << result.dump();
  EXPECT_DOUBLE_EQ(result["back_shot"]["area_ratio"].get<double>(), 1.0);

  const std::string refusedOut = d / "refused";
  const CliResult bad = runGarmcap(common + " --back " + scene + "/empty.png --out " + refusedOut);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("the back shot"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(refusedOut));
}

// A frame cut short in transfer (a JPEG without its end marker) is refused by name, with the
// frame's role, by `capture` and `calibrate`: libjpeg decodes it into a partly grey frame with
// only a warning, and the pipeline then refused it for a wrong reason ("not a green screen").
// Nothing is written.
TEST(CaptureCli, ACutJpegFrameIsRefusedAsTruncated) {
  const TempDir d("capture_cli_cut");
  const std::string scene = d / "scene";
  const CliResult made =
      runGarmcap("render --type skirt --size 46 --chart french_women --form " + kForm +
                 " --seed 5 --width 480 --height 640 --image-format jpg --out " + scene);
  ASSERT_EQ(made.status, 0) << made.err;
  const std::string whole = readText(scene + "/dressed.jpg");
  ASSERT_GT(whole.size(), 1000u);
  const std::string cut = d / "cut.jpg";
  {
    std::ofstream f(cut, std::ios::binary);
    f.write(whole.data(), static_cast<std::streamsize>(whole.size() / 2));
  }
  const std::string out = d / "out";
  expectRefused(runGarmcap("capture --empty " + scene + "/empty.jpg --dressed " + cut +
                           " --calibration " + scene + "/calibration.json --out " + out),
                {"dressed frame", cut, "truncated JPEG"});
  expectRefused(
      runGarmcap("calibrate --form " + kForm + " --empty " + cut + " --out " + (d / "cal.json")),
      {"bare-form frame", cut, "truncated JPEG"});
  expectRefused(runGarmcap("capture --empty " + scene + "/empty.jpg --dressed " + (d / "none.jpg") +
                           " --calibration " + scene + "/calibration.json --out " + out),
                {"dressed frame", "none.jpg", "missing"});
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(d / "cal.json"));
}

// `rig eval` on a torso form: the station reads no sleeve on a form without arms, so a
// sleeveless truth (sleeve_length 0) left unread is not a missing reading; it is counted apart
// as not owed. Every other truth still counts (no reading is missing on these easy cases).
TEST(RigEvalCli, ASleevelessTruthOnAnArmlessFormIsNotMissing) {
  const TempDir d("rig_eval_torso");
  const std::string rig = d / "rig";
  ASSERT_EQ(runGarmcap("rig make --count 3 --seed 5 --width 432 --height 576 --chart korean_women "
                       "--torso --out " +
                       rig)
                .status,
            0);
  int sleeveless = 0;
  const auto index = readJson(rig + "/rig.json");
  for (const auto& c : index.at("cases")) {
    const auto truth = readJson(rig + "/" + c.at("dir").get<std::string>() + "/truth.json");
    const auto& m = truth.at("measurements");
    if (m.contains("sleeve_length") && m.at("sleeve_length").get<double>() == 0.0)
      ++sleeveless;
  }
  ASSERT_GE(sleeveless, 1) << "the rig has no sleeveless top or dress to check";
  const std::string out = d / "eval";
  const CliResult r = runGarmcap("rig eval " + rig + " --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto eval = readJson(out + "/eval.json");
  const auto& summary = eval.at("summary");
  EXPECT_EQ(summary.at("readings_not_owed").get<int>(), sleeveless);
  EXPECT_EQ(summary.at("readings_missing").get<int>(), 0);
  EXPECT_FALSE(summary.at("measurements").contains("sleeve_length"));
  for (const auto& c : eval.at("cases")) {
    if (!c.contains("missing"))
      continue;
    for (const auto& k : c.at("missing")) {
      EXPECT_NE(k.get<std::string>(), "sleeve_length") << c.at("id");
    }
  }
}
