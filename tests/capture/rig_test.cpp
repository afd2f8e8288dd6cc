// Rig reader: the committed CI rig reads back; PNG and JPEG cases load; missing, doubled,
// corrupt, truncated and mismatched frames are refused with the files named.
#include "garmcap/capture/rig.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "common/temp_folder.h"
#include "garmcap/sim/garment_model.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

namespace garmcap::capture {

using sim::garmentMeasurementNames;
// The rig cases here are rendered by the simulator (its own target, garmcap::sim).
using sim::randomScene;
using sim::RandomSceneOptions;
using sim::SceneRenderer;
using sim::writeCase;
namespace {

const std::filesystem::path kRig = std::filesystem::path(GARMCAP_TEST_DATA_DIR) / "rig";
const std::string kForm =
    std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";

namespace fs = std::filesystem;

// Every case and index a test writes lives under one folder, removed when the binary exits.
const fs::path& scratch() {
  static const garmcap::testing::TempFolder folder("garmcap_rig_test");
  return folder.path();
}

// The frames of the committed case_000 (whatever format it holds them in), decoded once.
const RigCase& committedCase() {
  static const RigCase c = loadRigCase(kRig / "case_000");
  return c;
}

// A copy of the committed case_000 whose two frames are written in `format` (JPEG at quality
// `quality`) and nothing else.
fs::path copyCase(const std::string& name, RigImageFormat format = RigImageFormat::kPng,
                  int quality = kDefaultJpegQuality) {
  const auto dir = scratch() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* f : {"truth.json", "calibration.json", "scene.json"})
    fs::copy_file(kRig / "case_000" / f, dir / f);
  const RigImageOptions o{format, quality};
  writeRigFrame(dir, "empty", committedCase().empty, o);
  writeRigFrame(dir, "dressed", committedCase().dressed, o);
  return dir;
}

// A one-case rig index naming `caseDir` (absolute), with `extra` fields.
fs::path indexFor(const fs::path& caseDir, const std::string& extra = "") {
  const auto dir = caseDir.parent_path() / (caseDir.filename().string() + "_index");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "rig.json") << R"({"format": "garmcap-rig", "version": 1, )" << extra
                                  << R"("cases": [{"id": "c", "dir": ")" << caseDir.string()
                                  << R"(", "type": "top", "attributes": {}, "hard": false}]})";
  return dir;
}

std::string rigErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const RigError& e) {
    return e.what();
  }
  return "(no RigError)";
}

void expectHas(const std::string& msg, std::initializer_list<std::string> needles) {
  for (const auto& n : needles)
    EXPECT_NE(msg.find(n), std::string::npos) << "no '" << n << "' in: " << msg;
}

void writeBytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

std::string readBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Rig, CommittedRigReadsBackWithTruthOfEachType) {
  const Rig rig = readRig(kRig);
  ASSERT_GE(rig.cases.size(), 4u);
  for (const auto& info : rig.cases) {
    const RigCase c = loadRigCase(info.dir);
    EXPECT_EQ(c.empty.size(), c.dressed.size());
    EXPECT_EQ(c.empty.type(), CV_8UC3);
    EXPECT_EQ(c.empty.cols, rig.index.at("width").get<int>()) << info.id;
    EXPECT_EQ(c.empty.rows, rig.index.at("height").get<int>()) << info.id;
    EXPECT_EQ(c.truth["type"], info.type);
    for (const auto& n : garmentMeasurementNames(info.type)) {
      EXPECT_TRUE(c.truth["measurements"].contains(n)) << info.id << " " << n;
    }
    EXPECT_FALSE(c.calibration.is_null());
    // The calibration names the bare-form frame the case actually holds.
    EXPECT_EQ(c.calibration.at("empty_frame").get<std::string>(),
              rigFramePath(info.dir, "empty").filename().string());
    EXPECT_GT(cv::norm(c.empty, c.dressed, cv::NORM_L1), 0.0);
  }
}

const calib::FormModel& form() {
  static const calib::FormModel f = calib::FormModel::load(kForm);
  return f;
}

// A simulated case written as PNG reads back exactly; written as JPEG at the default quality it
// reads back within JPEG's loss. JPEG drops much of the per-pixel sensor noise and keeps the
// picture: on this 480x640 scene the mean error is 4.5 levels (PSNR 33 dB, largest 39), and
// after a 5x5 box blur, which averages the noise away, 0.75 levels (see the printout).
TEST(Rig, JpegCaseLoadsAsWrittenWithinJpegTolerance) {
  RandomSceneOptions so;
  so.size = {480, 640};
  so.hardFraction = 0;
  so.type = "dress";
  const SceneRenderer r(form(), randomScene(form(), kForm, 11, so));
  const cv::Mat empty = r.renderEmpty(), dressed = r.renderDressed();
  const auto base = scratch() / "sim";
  fs::remove_all(base);

  writeCase(r, base / "png");
  const RigCase p = loadRigCase(base / "png");
  EXPECT_EQ(cv::norm(p.empty, empty, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(p.dressed, dressed, cv::NORM_INF), 0.0);
  EXPECT_EQ(p.calibration.at("empty_frame"), "empty.png");

  writeCase(r, base / "jpg", {RigImageFormat::kJpeg, kDefaultJpegQuality});
  EXPECT_TRUE(fs::is_regular_file(base / "jpg" / "empty.jpg"));
  EXPECT_FALSE(fs::exists(base / "jpg" / "empty.png"));
  EXPECT_EQ(rigFramePath(base / "jpg", "dressed"), base / "jpg" / "dressed.jpg");
  const RigCase j = loadRigCase(base / "jpg");
  EXPECT_EQ(j.calibration.at("empty_frame"), "empty.jpg");
  EXPECT_EQ(j.truth.at("calibration").at("empty_frame"), "empty.jpg");
  for (const auto& [name, got, want] :
       {std::tuple{"empty", j.empty, empty}, std::tuple{"dressed", j.dressed, dressed}}) {
    ASSERT_EQ(got.size(), want.size()) << name;
    ASSERT_EQ(got.type(), CV_8UC3) << name;
    const double n = static_cast<double>(want.total() * 3);
    const double meanAbs = cv::norm(got, want, cv::NORM_L1) / n;
    const double psnr = cv::PSNR(got, want);
    cv::Mat gotBlur, wantBlur;
    cv::blur(got, gotBlur, {5, 5});
    cv::blur(want, wantBlur, {5, 5});
    const double blurredMeanAbs = cv::norm(gotBlur, wantBlur, cv::NORM_L1) / n;
    std::printf(
        "%s.jpg at quality %d: mean |error| %.2f levels, PSNR %.1f dB, max %.0f; after a 5x5 "
        "blur mean |error| %.2f\n",
        name, kDefaultJpegQuality, meanAbs, psnr, cv::norm(got, want, cv::NORM_INF),
        blurredMeanAbs);
    EXPECT_LT(meanAbs, 6.0) << name;
    EXPECT_GT(psnr, 30.0) << name;
    EXPECT_LT(blurredMeanAbs, 1.0) << name;
  }
  // A lower quality is a smaller file; the PNG is far larger than either.
  writeCase(r, base / "jpg_low", {RigImageFormat::kJpeg, 60});
  EXPECT_LT(fs::file_size(base / "jpg_low" / "dressed.jpg"),
            fs::file_size(base / "jpg" / "dressed.jpg"));
  EXPECT_LT(2 * fs::file_size(base / "jpg" / "dressed.jpg"),
            fs::file_size(base / "png" / "dressed.png"));
  // Rewriting the case as PNG leaves no JPEG behind.
  writeCase(r, base / "jpg");
  EXPECT_FALSE(fs::exists(base / "jpg" / "empty.jpg"));
  EXPECT_FALSE(fs::exists(base / "jpg" / "dressed.jpg"));
  EXPECT_NO_THROW(loadRigCase(base / "jpg"));
  fs::remove_all(base);
}

TEST(Rig, WritingAFrameInTheOtherFormatReplacesIt) {
  const auto dir = copyCase("switch", RigImageFormat::kPng);
  writeRigFrame(dir, "empty", committedCase().empty, {RigImageFormat::kJpeg, 90});
  EXPECT_FALSE(fs::exists(dir / "empty.png"));
  EXPECT_EQ(rigFramePath(dir, "empty"), dir / "empty.jpg");
  writeRigFrame(dir, "empty", committedCase().empty, {});
  EXPECT_FALSE(fs::exists(dir / "empty.jpg"));
  EXPECT_EQ(rigFramePath(dir, "empty"), dir / "empty.png");
}

TEST(Rig, JpegQualityOutsideOneToHundredIsRefused) {
  const auto dir = copyCase("quality", RigImageFormat::kPng);
  for (int q : {0, -5, 101}) {
    try {
      writeRigFrame(dir, "empty", committedCase().empty, {RigImageFormat::kJpeg, q});
      ADD_FAILURE() << "quality " << q << " was accepted";
    } catch (const std::invalid_argument& e) {
      expectHas(e.what(), {"1..100", std::to_string(q)});
    }
  }
  EXPECT_TRUE(fs::exists(dir / "empty.png"));  // nothing written, nothing removed
  EXPECT_FALSE(fs::exists(dir / "empty.jpg"));
  EXPECT_EQ(parseRigImageFormat("jpg"), RigImageFormat::kJpeg);
  EXPECT_EQ(parseRigImageFormat("png"), RigImageFormat::kPng);
  EXPECT_THROW(parseRigImageFormat("jpeg2000"), std::invalid_argument);
}

TEST(Rig, BothFormatsOfAFrameAreRefusedNamingTheFiles) {
  const auto dir = copyCase("both", RigImageFormat::kJpeg);
  fs::copy_file(dir / "dressed.jpg", dir / "dressed.png");  // content does not matter
  const std::string msg = rigErrorOf([&] { loadRigCase(dir); });
  expectHas(msg, {dir.string(), "dressed.png", "dressed.jpg", "both present"});
  const std::string atIndex = rigErrorOf([&] { readRig(indexFor(dir)); });
  expectHas(atIndex, {dir.string(), "dressed.png", "dressed.jpg", "both present", "case 'c'"});
}

TEST(Rig, NeitherFormatOfAFrameIsRefusedNamingTheFiles) {
  for (const RigImageFormat f : {RigImageFormat::kPng, RigImageFormat::kJpeg}) {
    const auto dir = copyCase("neither", f);
    fs::remove(dir / (std::string("empty.") + rigImageExtension(f)));
    const std::string msg = rigErrorOf([&] { loadRigCase(dir); });
    expectHas(msg, {(dir / "empty.png").string() + ": missing", "empty.jpg"});
    const std::string atIndex = rigErrorOf([&] { readRig(indexFor(dir)); });
    expectHas(atIndex, {(dir / "empty.png").string() + ": missing", "empty.jpg", "case 'c'"});
  }
}

TEST(Rig, CorruptPngIsNamed) {
  const auto dir = copyCase("corrupt", RigImageFormat::kPng);
  writeBytes(dir / "dressed.png", "\x89PNG\r\n\x1a\n garbage");
  expectHas(rigErrorOf([&] { loadRigCase(dir); }),
            {(dir / "dressed.png").string(), "not a readable image"});
  writeBytes(dir / "dressed.png", "GIF89a not a png");
  expectHas(rigErrorOf([&] { loadRigCase(dir); }), {(dir / "dressed.png").string(), "not a PNG"});
}

// libjpeg decodes a JPEG cut short into a partly grey image with only a warning on stderr: the
// reader refuses it by its missing end marker.
TEST(Rig, TruncatedJpegIsNamed) {
  const auto dir = copyCase("truncated", RigImageFormat::kJpeg);
  const std::string whole = readBytes(dir / "dressed.jpg");
  for (const std::size_t keep : {whole.size() / 2, whole.size() - 1, std::size_t{200}}) {
    writeBytes(dir / "dressed.jpg", whole.substr(0, keep));
    expectHas(rigErrorOf([&] { loadRigCase(dir); }),
              {(dir / "dressed.jpg").string(), "truncated JPEG", "FF D9"});
  }
  // Zero padding after the end marker (as UVC cameras deliver) is fine.
  writeBytes(dir / "dressed.jpg", whole + std::string(16, '\0'));
  EXPECT_NO_THROW(loadRigCase(dir));
}

TEST(Rig, GarbageJpegIsNamed) {
  const auto dir = copyCase("garbage", RigImageFormat::kJpeg);
  const fs::path file = dir / "empty.jpg";
  // Not a JPEG at all.
  writeBytes(file, std::string(4000, 'x'));
  expectHas(rigErrorOf([&] { loadRigCase(dir); }), {file.string(), "not a JPEG", "FF D8"});
  // A PNG under a .jpg name.
  writeRigFrame(dir, "scratch", committedCase().empty, {});
  fs::rename(dir / "scratch.png", file);
  expectHas(rigErrorOf([&] { loadRigCase(dir); }), {file.string(), "not a JPEG"});
  // A stub.
  writeBytes(file, "\xFF\xD8\xFF\xD9");
  expectHas(rigErrorOf([&] { loadRigCase(dir); }), {file.string(), "not a JPEG", "4 bytes"});
  // Well framed, garbage inside.
  writeBytes(file, "\xFF\xD8" + std::string(4000, '\x55') + "\xFF\xD9");
  expectHas(rigErrorOf([&] { loadRigCase(dir); }), {file.string(), "not a readable image"});
}

TEST(Rig, FramesOfDifferentSizesAreRefused) {
  for (const RigImageFormat f : {RigImageFormat::kPng, RigImageFormat::kJpeg}) {
    const auto dir = copyCase("sizes", f);
    cv::Mat small;
    cv::resize(committedCase().dressed, small,
               cv::Size(committedCase().dressed.cols - 2, committedCase().dressed.rows));
    writeRigFrame(dir, "dressed", small, {f, kDefaultJpegQuality});
    expectHas(rigErrorOf([&] { loadRigCase(dir); }),
              {"differs from", (dir / (std::string("empty.") + rigImageExtension(f))).string()});
  }
  // Mixed formats are read, and still held to one size.
  const auto dir = copyCase("sizes_mixed", RigImageFormat::kPng);
  cv::Mat small;
  cv::resize(committedCase().dressed, small, cv::Size(), 0.5, 0.5);
  writeRigFrame(dir, "dressed", small, {RigImageFormat::kJpeg, 90});
  expectHas(rigErrorOf([&] { loadRigCase(dir); }),
            {(dir / "dressed.jpg").string(), "differs from", (dir / "empty.png").string()});
}

// rig.json's "image_format", when given, is what every case holds.
TEST(Rig, ImageFormatOfTheIndexIsChecked) {
  const auto dir = copyCase("declared", RigImageFormat::kJpeg);
  EXPECT_NO_THROW(readRig(indexFor(dir, R"("image_format": "jpg", "jpeg_quality": 92, )")));
  EXPECT_NO_THROW(readRig(indexFor(dir)));
  expectHas(rigErrorOf([&] { readRig(indexFor(dir, R"("image_format": "png", )")); }),
            {(dir / "empty.jpg").string(), "image_format"});
  expectHas(rigErrorOf([&] { readRig(indexFor(dir, R"("image_format": "jpeg", )")); }),
            {"image_format", "jpeg"});
  expectHas(rigErrorOf([&] { readRig(indexFor(dir, R"("jpeg_quality": 120, )")); }),
            {"jpeg_quality"});
}

TEST(Rig, UnknownFieldInIndexIsRefused) {
  const auto dir = scratch() / "index";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "rig.json")
      << R"({"format": "garmcap-rig", "version": 1, "cases": [], "colour": 1})";
  EXPECT_THROW(readRig(dir), RigError);
}

}  // namespace
}  // namespace garmcap::capture
