#include "garmcap/pipeline/reference_garment.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/garment_measurer.h"

namespace garmcap::pipeline {
namespace {

// The bundled rig's calibration (the scanned form), its form path made absolute.
const CaptureContext& context() {
  static const auto ctx = [] {
    std::ifstream in(std::filesystem::path(GARMCAP_TEST_DATA_DIR) /
                     "rig/case_000/calibration.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["form"] =
        (std::filesystem::path(GARMCAP_SHARED_DIR) / "data/forms/garmentcode_mean_female/form.json")
            .string();
    return buildCaptureContext(j, kDefaultSizeChart);
  }();
  return *ctx;
}

cv::Mat1b draw(const std::string& type, std::map<std::string, std::string> attributes) {
  const auto& ctx = context();
  return drawReferenceGarment(referenceGarment(type, attributes, 1.0, ctx.body, *ctx.view),
                              *ctx.view);
}

int widthAtRow(const cv::Mat1b& mask, int row) {
  return cv::countNonZero(mask.row(row));
}

TEST(ReferenceGarment, PantsPartIntoLegsAndSkirtsDoNot) {
  const auto& view = *context().view;
  EXPECT_GE(partedLegsCm(draw("pants", {}), view), 5.0);
  EXPECT_LT(partedLegsCm(draw("skirt", {{"skirt", "h_line"}}), view), 5.0);
}

TEST(ReferenceGarment, ALineHemWiderThanHLineAndDressHangsBelowTheCrotch) {
  const auto& ctx = context();
  const auto& view = *ctx.view;
  const ReferenceGarment a = referenceGarment("skirt", {{"skirt", "a_line"}}, 1.0, ctx.body, view);
  const int hemRow = static_cast<int>(view.rowOfHeight(a.hemCm)) - 2;
  EXPECT_GT(widthAtRow(draw("skirt", {{"skirt", "a_line"}}), hemRow),
            widthAtRow(draw("skirt", {{"skirt", "h_line"}}), hemRow) + 10);
  EXPECT_GT(coveredBelowCrotchCm(draw("dress", {{"sleeve", "none"}, {"skirt", "h_line"}}), view),
            3.0);
  EXPECT_LT(coveredBelowCrotchCm(draw("top", {{"sleeve", "none"}}), view), 3.0);
}

TEST(ReferenceGarment, SleevesReachDownTheArm) {
  const auto& view = *context().view;
  const auto sleeve = [&](const char* s) {
    const auto m = measureGarment(draw("top", {{"sleeve", s}}), view, "top").measurements;
    const auto it = m.find("sleeve_length");
    return it == m.end() ? 0.0 : it->second;
  };
  EXPECT_LT(sleeve("none"), 5.0);
  EXPECT_GT(sleeve("short"), sleeve("none") + 8.0);
  EXPECT_GT(sleeve("long"), sleeve("short") + 20.0);
}

TEST(ReferenceGarment, RejectsAnUnknownTypeOrAMissingAttribute) {
  const auto& ctx = context();
  EXPECT_THROW(referenceGarment("coat", {}, 1.0, ctx.body, *ctx.view), std::invalid_argument);
  EXPECT_THROW(referenceGarment("skirt", {}, 1.0, ctx.body, *ctx.view), std::invalid_argument);
}

}  // namespace
}  // namespace garmcap::pipeline
