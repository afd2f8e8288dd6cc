// The GarmentCode JSON of every GRADED size (issue 18): every garment type drafted at a size of
// each chart the station ships, graded by DSW to every size of that chart (the station's size
// run, dsw::gradeSizeRun), stored and read back as the station and the hub store it (the
// pattern JSON), written as GarmentCode and read back independently of the writer
// (tests/drafts/garmentcode_rebuild.h: loops within 1 mm of the graded pieces, every seam and
// dart stitched edge to edge). The drafts tests cover drafted sizes only; a graded size is not
// a draft (its points are warped one by one, so corners and seam ends that coincide in a draft
// coincide only to rounding, and bends change their angle).
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "drafts/garmentcode_rebuild.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_run.h"

namespace garmcap::dsw {
namespace {

using nlohmann::json;

// One source size per chart: the smallest, the middle and the largest, so that every size is
// reached from below and from above (a captured garment's sample size can be any of them).
// Sizes written and read back, and the largest distance of a loop from its piece (cm).
struct Tally {
  int sizes = 0;
  double worstCm = 0;
};

void checkRun(const drafts::SizeChart& chart, const drafts::Pattern& source, Tally& tally) {
  const auto run = gradeSizeRun(source, chart);
  ASSERT_TRUE(run) << run.error().message;
  ASSERT_EQ(run->sizes, chart.sizes);
  for (std::size_t i = 0; i < run->sizes.size(); ++i) {
    SCOPED_TRACE("graded to " + run->sizes[i]);
    // As stored by the station and the hub, and read back by their garmentcode.json routes.
    const drafts::Pattern stored =
        drafts::patternFromJsonValue(drafts::patternToJsonValue(run->patterns[i]), "stored");
    std::string text;
    try {
      text = drafts::garmentCodeJson(stored, {"T-1", run->sizes[i]});
    } catch (const drafts::GarmentCodeExportError& e) {
      ADD_FAILURE() << "refused: " << e.what();
      continue;
    }
    drafts::rebuild::checkSpec(stored, json::parse(text), &tally.worstCm);
    ++tally.sizes;
  }
}

void checkRunsFrom(const drafts::SizeChart& chart, const std::string& type,
                   const std::string& sourceSize, Tally& tally) {
  SCOPED_TRACE(chart.name + " " + type + " from " + sourceSize);
  checkRun(chart, drafts::draftGarment(type, chart.body(sourceSize)), tally);
}

TEST(GradedGarmentCode, EverySizeOfEverySizeRunRebuildsWithinAMillimetre) {
  Tally tally;
  for (const auto& chart : drafts::sizeCharts())
    for (const auto& t : drafts::garmentTypes())
      for (const std::string& from :
           {chart.sizes.front(), chart.sizes[chart.sizes.size() / 2], chart.sizes.back()})
        checkRunsFrom(chart, t.name, from, tally);
  std::printf("%d graded sizes rebuilt, loops within %.4f cm of the pieces\n", tally.sizes,
              tally.worstCm);
}

// The station's designed dress (tests/data/designs/dress_55.json: scoop neckline, skirt flared
// 8 cm per side seam, drafted on korean_women 55), the source the hub's graded files are
// tested with, graded to every chart.
TEST(GradedGarmentCode, TheDesignedDressRebuildsInEverySizeOfEveryChart) {
  const drafts::Pattern source =
      drafts::readPatternJson(std::string(GARMCAP_TEST_DATA_DIR) + "/designs/dress_55.json");
  Tally tally;
  for (const auto& chart : drafts::sizeCharts()) {
    SCOPED_TRACE(chart.name + " designed dress");
    checkRun(chart, source, tally);
  }
  std::printf("%d graded sizes rebuilt, loops within %.4f cm of the pieces\n", tally.sizes,
              tally.worstCm);
}

}  // namespace
}  // namespace garmcap::dsw
