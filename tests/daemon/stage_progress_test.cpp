#include "garmcap/daemon/stage_progress.h"

#include <gtest/gtest.h>

namespace garmcap::daemon {
namespace {

using Timings = std::vector<std::pair<std::string, double>>;

const Timings kPipelineOrder = {{"context", 1}, {"registration", 1}, {"masks", 1},
                                {"grabcut", 1}, {"type", 1},         {"measure", 1},
                                {"pattern", 1}, {"images", 1},       {"texture", 1}};

TEST(StageProgress, RisesThroughThePipelineAndNamesTheStageThatRunsNow) {
  StageProgress p;
  double last = 0;
  for (std::size_t i = 0; i < kPipelineOrder.size(); ++i) {
    const auto step = p.after(kPipelineOrder[i].first);
    EXPECT_GT(step.fraction, last) << kPipelineOrder[i].first;
    last = step.fraction;
    EXPECT_EQ(step.next, i + 1 < kPipelineOrder.size() ? kPipelineOrder[i + 1].first : "");
  }
  EXPECT_DOUBLE_EQ(last, 1.0);
}

TEST(StageProgress, SharesFollowWhatThisStationMeasured) {
  StageProgress p;
  // A station whose segmentation dominates: masks 9 s, everything else 0.1 s.
  Timings slowMasks = kPipelineOrder;
  for (auto& [stage, ms] : slowMasks)
    ms = stage == "masks" ? 9000 : 100;
  for (int i = 0; i < 20; ++i)
    p.learn(slowMasks);
  const double total = 9000 + 8 * 100;
  EXPECT_NEAR(p.after("registration").fraction, 200 / total, 0.01);
  EXPECT_NEAR(p.after("masks").fraction, 9200 / total, 0.01);
  // One odd capture moves the shares, but does not take them over.
  Timings fastMasks = kPipelineOrder;
  for (auto& [stage, ms] : fastMasks)
    ms = 100;
  p.learn(fastMasks);
  const double afterOne = p.after("masks").fraction;
  EXPECT_LT(afterOne, 9200 / total);
  EXPECT_GT(afterOne, 0.5);
}

TEST(StageProgress, NewStagesGoAfterTheirPredecessorAndSkippedOnesKeepTheirPlace) {
  StageProgress p;
  // No texture this time, and a new "despill" stage after the images.
  p.learn({{"context", 5},
           {"registration", 60},
           {"masks", 250},
           {"grabcut", 300},
           {"type", 60},
           {"measure", 40},
           {"pattern", 30},
           {"images", 150},
           {"despill", 50}});
  EXPECT_EQ(p.after("images").next, "despill");
  EXPECT_EQ(p.after("despill").next, "texture");
  EXPECT_DOUBLE_EQ(p.after("texture").fraction, 1.0);
  // A stage never seen gives nothing to go on: the caller keeps its value.
  EXPECT_EQ(p.after("unheard of").fraction, 0.0);
  EXPECT_EQ(p.after("unheard of").next, "");
}

TEST(StageProgress, RepeatedStageNamesAddUpAndBadDurationsAreIgnored) {
  StageProgress p;
  Timings t = kPipelineOrder;
  for (auto& [stage, ms] : t)
    ms = 100;
  t.push_back({"images", 800});  // the images stage reported twice: 900 ms in all
  t.push_back({"masks", -5});    // a clock that went backwards is no measurement
  for (int i = 0; i < 30; ++i)
    p.learn(t);
  const double total = 8 * 100 + 900;
  EXPECT_NEAR(p.after("pattern").fraction, 700 / total, 0.01);
  EXPECT_NEAR(p.after("images").fraction, 1600 / total, 0.01);
}

}  // namespace
}  // namespace garmcap::daemon
