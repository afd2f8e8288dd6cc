// Issue 18: a piece cut on the fold must have a straight fold edge, in the drafted size and in
// every graded size; a centre line the draft shapes is a seam (cut 2), never a fold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_run.h"

namespace garmcap::dsw {
namespace {

using drafts::Point2;

// The centre edge of a panel by geometry alone: recipes draw half patterns, the back from its
// centre back at the left (least x), the front to its centre front at the right (docs/drafts.md,
// Conventions). From a vertex at that x, the chain of outline edges within 10 degrees of
// vertical on both sides; returns its vertices (empty for a piece neither back nor front).
std::vector<Point2> centreChain(const drafts::Panel& p) {
  const auto& o = p.outline;
  const int n = static_cast<int>(o.size());
  auto at = [&](int i) { return o[static_cast<std::size_t>(((i % n) + n) % n)]; };
  auto nearVertical = [&](int i) {
    const Point2 d = at(i + 1) - at(i);
    return d.norm() > 1e-9 && std::abs(d.x()) < std::tan(10.0 * M_PI / 180) * std::abs(d.y());
  };
  const bool back = p.name.find("back") != std::string::npos;
  if (!back && p.name.find("front") == std::string::npos)
    return {};
  int v = 0;
  for (int i = 1; i < n; ++i)
    if (back ? at(i).x() < at(v).x() : at(i).x() > at(v).x())
      v = i;
  int lo = v, hi = v;  // the chain's vertices lo..hi
  while (hi - lo < n && nearVertical(hi))
    ++hi;
  while (hi - lo < n && nearVertical(lo - 1))
    --lo;
  std::vector<Point2> chain;
  for (int k = lo; k <= hi; ++k)
    chain.push_back(at(k));
  return chain;
}

// Largest distance of a chain's vertices from the line through its two ends.
double offLine(const std::vector<Point2>& chain) {
  const Point2 a = chain.front(), d = (chain.back() - a).normalized();
  double worst = 0;
  for (const auto& v : chain) {
    const Point2 r = v - a;
    worst = std::max(worst, std::abs(r.x() * d.y() - r.y() * d.x()));
  }
  return worst;
}

void expectStraightFolds(const drafts::Pattern& pattern, const std::string& what, int& folds) {
  for (const auto& panel : pattern.panels) {
    if (!panel.cutOnFold)
      continue;
    ++folds;
    double yMin = 1e300, yMax = -1e300;
    for (const auto& v : panel.outline) {
      yMin = std::min(yMin, v.y());
      yMax = std::max(yMax, v.y());
    }
    const auto chain = centreChain(panel);
    ASSERT_GE(chain.size(), 2u) << what << " " << panel.name;
    EXPECT_GT(std::abs(chain.back().y() - chain.front().y()), 0.6 * (yMax - yMin))
        << what << " " << panel.name << ": the fold must run the piece's centre line";
    EXPECT_LE(offLine(chain), 0.01)
        << what << " " << panel.name << ": its fold edge is not straight";
  }
}

TEST(FoldEdge, EveryPieceCutOnTheFoldHasAStraightFoldInEveryGradedSize) {
  const drafts::SizeChart& chart = drafts::sizeChart("korean_women");
  for (const auto& type : drafts::garmentTypes()) {
    if (type.name == "sleeve")
      continue;  // drafted with a bodice (dress, blouse, sweater), covered there
    const drafts::Pattern source = drafts::draftGarment(type.name, chart.body("55"));
    int folds = 0;
    expectStraightFolds(source, type.name + " drafted", folds);
    auto run = gradeSizeRun(source, chart);
    ASSERT_TRUE(run.ok()) << type.name << ": " << run.error().message;
    for (std::size_t i = 0; i < run->sizes.size(); ++i)
      expectStraightFolds(run->patterns[i], type.name + " graded to " + run->sizes[i], folds);
    // Drafted directly for every size as well (the draft's own geometry, not the warp's).
    for (const auto& size : chart.sizes)
      expectStraightFolds(drafts::draftGarment(type.name, chart.body(size)),
                          type.name + " drafted for " + size, folds);
  }
}

// The dress: bodice back and skirt back are cut alike (both twice, sewn at the centre back).
TEST(FoldEdge, DressBacksAreCutAlike) {
  const drafts::Pattern dress =
      drafts::draftGarment("dress", drafts::sizeChart("korean_women").body("55"));
  const auto& bodice = dress.panel("bodice_back");
  const auto& skirt = dress.panel("skirt_back");
  EXPECT_EQ(bodice.cutOnFold, skirt.cutOnFold);
  EXPECT_EQ(bodice.cutCount, skirt.cutCount);
}

}  // namespace
}  // namespace garmcap::dsw
