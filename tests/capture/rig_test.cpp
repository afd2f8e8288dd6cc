// Rig reader: the committed CI rig reads back; missing, corrupt and mismatched frames are
// refused with the file named.
#include "garmcap/capture/rig.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "garmcap/calib/garment_model.h"

namespace garmcap::capture {

using calib::garmentMeasurementNames;
namespace {

const std::filesystem::path kRig = std::filesystem::path(GARMCAP_TEST_DATA_DIR) / "rig";

std::filesystem::path copyCase(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("garmcap_rig_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::copy(kRig / "case_000", dir);
  return dir;
}

TEST(Rig, CommittedRigReadsBackWithTruthOfEachType) {
  const Rig rig = readRig(kRig);
  ASSERT_GE(rig.cases.size(), 4u);
  for (const auto& info : rig.cases) {
    const RigCase c = loadRigCase(info.dir);
    EXPECT_EQ(c.empty.size(), c.dressed.size());
    EXPECT_EQ(c.truth["type"], info.type);
    for (const auto& n : garmentMeasurementNames(info.type)) {
      EXPECT_TRUE(c.truth["measurements"].contains(n)) << info.id << " " << n;
    }
    EXPECT_FALSE(c.calibration.is_null());
    EXPECT_GT(cv::norm(c.empty, c.dressed, cv::NORM_L1), 0.0);
  }
}

TEST(Rig, CorruptImageIsNamed) {
  const auto dir = copyCase("corrupt");
  std::ofstream(dir / "dressed.png", std::ios::binary | std::ios::trunc) << "\x89PNG\r\n garbage";
  try {
    loadRigCase(dir);
    FAIL() << "a corrupt PNG was accepted";
  } catch (const RigError& e) {
    EXPECT_NE(std::string(e.what()).find("dressed.png"), std::string::npos) << e.what();
  }
}

TEST(Rig, MissingImageIsNamed) {
  const auto dir = copyCase("missing");
  std::filesystem::remove(dir / "empty.png");
  try {
    loadRigCase(dir);
    FAIL() << "a case without empty.png was accepted";
  } catch (const RigError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.png: missing"), std::string::npos) << e.what();
  }
}

TEST(Rig, FramesOfDifferentSizesAreRefused) {
  const auto dir = copyCase("sizes");
  cv::Mat small = cv::imread((dir / "dressed.png").string());
  cv::resize(small, small, cv::Size(small.cols - 2, small.rows));
  cv::imwrite((dir / "dressed.png").string(), small);
  EXPECT_THROW(loadRigCase(dir), RigError);
}

TEST(Rig, UnknownFieldInIndexIsRefused) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("garmcap_rig_test_index_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "rig.json")
      << R"({"format": "garmcap-rig", "version": 1, "cases": [], "colour": 1})";
  EXPECT_THROW(readRig(dir), RigError);
}

}  // namespace
}  // namespace garmcap::capture
