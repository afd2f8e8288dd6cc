// Markers (marker.h): which pieces go on the fabric and how they are turned, checked against the
// drafted panels' own cut lines; overlap, efficiency and the files are checked from the CLI's
// output by nested_marker_check.py.
#include "garmcap/drafts/marker.h"

#include <gtest/gtest.h>

#include <cmath>

#include "garmcap/drafts/geometry_polygon.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/seam_allowance.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::drafts {
namespace {

// Issue 18: the piece limit is a parameter (default kDefaultMarkerMaxPieces), checked before
// any nesting, and its refusal names the count and the limit.
TEST(Marker, MorePiecesThanTheLimitAreRefusedNamingIt) {
  const Pattern pat = draftGarment("skirt_h", sizeChart("korean_women").body("66"));
  int perSize = 0;
  for (const auto& p : pat.panels)
    perSize += std::max(1, p.cutCount);
  ASSERT_GE(perSize, 2);
  EXPECT_EQ(MarkerOptions{}.maxPieces, kDefaultMarkerMaxPieces);
  // Exactly at the limit: laid.
  EXPECT_EQ(layMarker({{"66", pat}}, {150.0, 0.2, perSize}).pieces.size(),
            static_cast<size_t>(perSize));
  // One over: refused, whatever the sizes.
  try {
    layMarker({{"55", pat}, {"66", pat}}, {150.0, 0.2, 2 * perSize - 1});
    FAIL() << "no MarkerLimitError";
  } catch (const MarkerLimitError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(std::to_string(2 * perSize) + " pieces"), std::string::npos) << what;
    EXPECT_NE(what.find("limit of " + std::to_string(2 * perSize - 1)), std::string::npos) << what;
    EXPECT_NE(what.find("max_pieces"), std::string::npos) << what;
  }
  // The default holds a five-size run of the skirt; a limit below 1 is refused.
  EXPECT_LE(5 * perSize, kDefaultMarkerMaxPieces);
  EXPECT_THROW(layMarker({{"66", pat}}, {150.0, 0.2, 0}), MarkerError);
}

TEST(Marker, CutCountsFoldsAndMirrorsOfASkirt) {
  const Pattern pat = draftGarment("skirt_a", sizeChart("korean_women").body("66"));
  const Marker m = layMarker({{"66", pat}}, {150.0, 0.2});
  size_t want = 0;
  for (const auto& p : pat.panels)
    want += static_cast<size_t>(std::max(1, p.cutCount));
  ASSERT_EQ(m.pieces.size(), want);
  double area = 0;
  for (const auto& p : pat.panels) {
    const double half = polygonArea(cutOutline(p, pat));
    int copies = 0, mirrors = 0;
    for (const auto& q : m.pieces) {
      if (q.panel != p.name)
        continue;
      ++copies;
      mirrors += q.mirrored ? 1 : 0;
      EXPECT_EQ(q.unfolded, p.cutOnFold) << p.name;
      // A fold piece opened out is twice the half's cut line; others are the cut line itself.
      EXPECT_NEAR(polygonArea(q.cutLine), (p.cutOnFold ? 2 : 1) * half, 1e-6 * half) << p.name;
      EXPECT_NEAR(q.areaCm2, polygonArea(q.cutLine), 1e-6 * half);
      // Grain along the fabric's length: both ends at the same y.
      EXPECT_NEAR(q.grainStart.y(), q.grainEnd.y(), 1e-6) << p.name;
      for (const auto& v : q.cutLine) {
        EXPECT_GE(v.y(), -1e-6);
        EXPECT_LE(v.y(), 150.0 + 1e-6);
        EXPECT_GE(v.x(), -1e-6);
        EXPECT_LE(v.x(), m.lengthCm + 1e-6);
      }
    }
    EXPECT_EQ(copies, std::max(1, p.cutCount)) << p.name;
    EXPECT_EQ(mirrors, std::max(1, p.cutCount) / 2) << p.name;
    area += copies * (p.cutOnFold ? 2 : 1) * half;
  }
  EXPECT_NEAR(m.pieceAreaCm2, area, 1e-6 * area);
  EXPECT_NEAR(m.efficiency, area / (m.lengthCm * 150.0), 1e-9);
  EXPECT_GT(m.efficiency, 0.5) << "a skirt nests better than one piece per row";
  EXPECT_LE(m.efficiency, 1.0);
}

TEST(Marker, RefusesFabricNarrowerThanAPiece) {
  const Pattern pat = draftGarment("skirt_a", sizeChart("korean_women").body("66"));
  try {
    layMarker({{"66", pat}}, {20.0, 0.2});
    FAIL() << "a 20 cm fabric cannot hold a skirt panel";
  } catch (const MarkerError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("wider than the fabric (20.0 cm)"), std::string::npos) << what;
    EXPECT_EQ(what.rfind("marker: panel '", 0), 0u) << "names the piece: " << what;
    EXPECT_NE(what.find("' of size 66 is "), std::string::npos) << what;
  }
  EXPECT_THROW(layMarker({}, {150.0, 0.2}), MarkerError);
}

}  // namespace
}  // namespace garmcap::drafts
