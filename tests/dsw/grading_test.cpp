// Grading tests: the source design, the seed's experiment (table 4.3) with ease preserved,
// dart compensation (table 4.1's case), the five steps on hand-made patterns, base-draft
// grading, and bad input.
#include "garmcap/dsw/grading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "design_dress.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/dsw/base_draft.h"
#include "table4_3.h"

namespace garmcap::dsw {
namespace {

namespace fs = std::filesystem;
const fs::path kData = GARMCAP_TEST_DATA_DIR;

drafts::Measurements body(const std::string& size) {
  return drafts::readMeasurementsJson(kData / "bodies" / ("table4_2_" + size + ".json"));
}

drafts::Pattern sourceDress() {
  return drafts::readPatternJson(kData / "designs" / "dress_55.json");
}

TEST(DesignDress, CommittedFileIsTheGeneratorOutput) {
  const drafts::Pattern generated = testing::designDress(body("55"));
  const fs::path file = kData / "designs" / "dress_55.json";
  if (std::getenv("GARMCAP_REGENERATE") != nullptr)
    drafts::writePatternJson(file, generated);
  const drafts::Pattern committed = drafts::readPatternJson(file);
  ASSERT_EQ(committed.panels.size(), generated.panels.size());
  for (std::size_t i = 0; i < committed.panels.size(); ++i) {
    ASSERT_EQ(committed.panels[i].outline.size(), generated.panels[i].outline.size())
        << committed.panels[i].name;
    for (std::size_t k = 0; k < committed.panels[i].outline.size(); ++k)
      EXPECT_LT((committed.panels[i].outline[k] - generated.panels[i].outline[k]).norm(), 1e-6)
          << committed.panels[i].name << " vertex " << k
          << " (rerun with GARMCAP_REGENERATE=1 after a recipe change)";
  }
}

TEST(DesignDress, DiffersFromItsDraft) {
  const drafts::Pattern design = sourceDress();
  const drafts::Pattern& draft = design;  // regions are the size-55 draft's panels
  const auto& front = design.panel("bodice_front");
  const auto& frontRegion = draft.region("bodice_front");
  double maxNeck = 0;
  for (std::size_t k = 0; k < front.outline.size(); ++k)
    maxNeck = std::max(maxNeck, front.outline[k].y() - frontRegion.polygon[k].y());
  EXPECT_NEAR(maxNeck, testing::kNecklineDropCm, 1e-9);
  const auto& skirt = design.panel("skirt_front");
  const auto& skirtRegion = draft.region("skirt_front");
  double maxFlare = 0;
  for (std::size_t k = 0; k < skirt.outline.size(); ++k)
    maxFlare = std::max(maxFlare, (skirt.outline[k] - skirtRegion.polygon[k]).norm());
  EXPECT_NEAR(maxFlare, testing::kHemFlareCm, 1e-9);
}

TEST(Grading, SameBodyReproducesThePanels) {
  const drafts::Pattern src = sourceDress();
  auto graded = gradePattern(src, src.measurements);
  ASSERT_TRUE(graded.ok()) << graded.error().message;
  for (std::size_t i = 0; i < src.panels.size(); ++i) {
    const auto a = flattenPanel(src.panels[i]);
    const auto b = flattenPanel(graded->panels[i]);
    for (std::size_t k = 0; k < a.size(); ++k)
      EXPECT_LT((a[k] - b[k]).norm(), 1e-9) << src.panels[i].name;
  }
}

TEST(Grading, Table43EasePreservedWithinHalfACentimetre) {
  const drafts::Pattern src = sourceDress();
  const auto rows = testing::table43(src, {"44", "66", "77"}, GradeOptions{});
  for (const auto& row : rows) {
    for (const auto& [size, value] : row.graded) {
      const double easeSource = row.source - row.sourceBody;
      const double easeGraded = value - row.targetBody.at(size);
      EXPECT_LT(std::abs(easeGraded - easeSource), 0.5)
          << row.label << " size " << size << ": graded " << value << ", body "
          << row.targetBody.at(size) << ", source ease " << easeSource;
    }
  }
  if (std::getenv("GARMCAP_REGENERATE") != nullptr) {
    std::ofstream(fs::path(GARMCAP_TEST_DATA_DIR).parent_path().parent_path() / "docs" /
                  "dsw_table4_3.md")
        << testing::table43Markdown(src, rows);
  }
}

TEST(Grading, GradedPanelsGrowWithTheBody) {
  const drafts::Pattern src = sourceDress();
  double last = 0;
  for (const std::string size : {"44", "55", "66", "77"}) {
    auto g = gradePattern(src, body(size));
    ASSERT_TRUE(g.ok()) << g.error().message;
    const double bust = drafts::measurePattern(*g).at("bust_circ");
    EXPECT_GT(bust, last + 4) << size;
    last = bust;
  }
}

TEST(DartCompensation, Table41CaseReturnsTheWaistMarginToThreeCentimetres) {
  // Table 4.1's case: a bodice whose waist does not follow the draft. The designer took the
  // size-55 draft (ease_waist 6) and widened its waist darts until the garment waist was the
  // body's + 3.00 cm; graded to 77 the margin drifts, and dart compensation restores it.
  const drafts::Measurements b55 = body("55"), b77 = body("77");
  drafts::Pattern src = drafts::draftGarment("dress", b55);
  auto designed = compensateDarts(src, b55.get("waist_circ"), 3.0);
  ASSERT_TRUE(designed.ok()) << designed.error().message;
  ASSERT_NEAR(drafts::measurePattern(src).at("waist_circ") - b55.get("waist_circ"), 3.0, 0.05);
  auto without = gradePattern(src, b77);
  ASSERT_TRUE(without.ok()) << without.error().message;
  const double marginWithout =
      drafts::measurePattern(*without).at("waist_circ") - b77.get("waist_circ");
  GradeOptions comp;
  comp.dartCompensation = true;
  auto with = gradePattern(src, b77, comp);
  ASSERT_TRUE(with.ok()) << with.error().message;
  const double marginWith = drafts::measurePattern(*with).at("waist_circ") - b77.get("waist_circ");
  EXPECT_NEAR(marginWith, 3.0, 0.05);
  RecordProperty("margin_without", std::to_string(marginWithout));
  RecordProperty("margin_with", std::to_string(marginWith));
  std::printf("table 4.1 case: margin source 3.00, DSW without DA %.2f, with DA %.2f\n",
              marginWithout, marginWith);
  // Configurable margin.
  comp.marginCm = 5.0;
  auto five = gradePattern(src, b77, comp);
  ASSERT_TRUE(five.ok()) << five.error().message;
  EXPECT_NEAR(drafts::measurePattern(*five).at("waist_circ") - b77.get("waist_circ"), 5.0, 0.05);
}

// Finished waist from the pattern's waist seams, not from measurePattern's girth: the sewn
// length of the bodice side of every waist_* seam (darts closed) times its pieces.
double waistSeamCm(const drafts::Pattern& p) {
  double w = 0;
  for (const auto& s : p.seams) {
    if (s.name.rfind("waist", 0) != 0)
      continue;
    const auto& panel = p.panel(s.a.panel);
    w += drafts::sewnEdgeLength(panel, s.a) * panel.cutCount * (panel.cutOnFold ? 2 : 1);
  }
  return w;
}

TEST(DartCompensation, KeepsTheBaseSizeAndTheDesignedEase) {
  // Issue 18: --dart-compensation turned the size-55 dress's waist 71 (body 65 + ease 6) into 68
  // (a fixed 3 cm margin). Its margin is now the source's own ease: the base size comes back
  // unchanged, every other size keeps the designed ease, and the hip is never touched.
  const drafts::Pattern src = sourceDress();
  const drafts::Measurements b55 = body("55");
  const double ease = src.design.at("ease_waist");
  ASSERT_NEAR(waistSeamCm(src), b55.get("waist_circ") + ease, 0.05);
  auto own = waistMargin(src);
  ASSERT_TRUE(own.ok()) << own.error().message;
  EXPECT_NEAR(*own, ease, 0.05);
  GradeOptions comp;
  comp.dartCompensation = true;
  for (const std::string size : {"44", "55", "66", "77"}) {
    SCOPED_TRACE(size);
    const drafts::Measurements b = body(size);
    auto without = gradePattern(src, b);
    auto with = gradePattern(src, b, comp);
    ASSERT_TRUE(without.ok()) << without.error().message;
    ASSERT_TRUE(with.ok()) << with.error().message;
    const double wWithout = waistSeamCm(*without), wWith = waistSeamCm(*with);
    std::printf("size %s: waist seam without compensation %.2f, with %.2f (body %.1f + %.1f)\n",
                size.c_str(), wWithout, wWith, b.get("waist_circ"), ease);
    EXPECT_NEAR(wWith, b.get("waist_circ") + ease, 0.1);
    EXPECT_NEAR(wWith, wWithout, 0.1);  // the draft already keeps the ease; nothing to restore
    EXPECT_NEAR(drafts::measurePattern(*with).at("hip_circ"),
                drafts::measurePattern(*without).at("hip_circ"), 1e-6);
    if (size == "55") {
      EXPECT_NEAR(wWith, 71.0, 0.05);
      // The skirt side of the waist seams matches the bodice side after compensation.
      for (const auto& s : with->seams) {
        if (s.name.rfind("waist", 0) == 0) {
          EXPECT_NEAR(drafts::sewnEdgeLength(with->panel(s.a.panel), s.a),
                      drafts::sewnEdgeLength(with->panel(s.b.panel), s.b), 0.05)
              << s.name;
        }
      }
    }
  }
  // An explicit margin still overrides the ease (a design change the user asks for).
  comp.marginCm = 3.0;
  auto three = gradePattern(src, b55, comp);
  ASSERT_TRUE(three.ok()) << three.error().message;
  EXPECT_NEAR(waistSeamCm(*three), b55.get("waist_circ") + 3.0, 0.1);
}

TEST(Grading, CapAndShortSleeveDressesGradeAcrossTheChart) {
  // Issue 18 item 6: sleeves shorter than their cap are drafted as cap sleeves; their regions
  // keep the vertex counts of a sleeved draft, so DSW grades them like any other design.
  const drafts::Measurements b55 = body("55");
  for (const double cm : {8.0, 15.0, 22.0}) {
    SCOPED_TRACE(std::to_string(cm) + " cm sleeve");
    const double fraction = cm / b55.get("arm_shoulder_tip_to_wrist");
    const drafts::Pattern src = drafts::draftGarment("dress", b55, {{"sleeve_length", fraction}});
    for (const std::string size : {"44", "66", "77"}) {
      auto g = gradePattern(src, body(size));
      ASSERT_TRUE(g.ok()) << size << ": " << g.error().message;
      const auto m = drafts::measurePattern(*g);
      EXPECT_NEAR(m.at("sleeve_length"), fraction * body(size).get("arm_shoulder_tip_to_wrist"),
                  0.3)
          << size;
      for (const auto& s : g->seams) {
        EXPECT_NEAR(drafts::sewnEdgeLength(g->panel(s.b.panel), s.b) -
                        drafts::sewnEdgeLength(g->panel(s.a.panel), s.a),
                    s.easeCm, 0.3)
            << size << " " << s.name;
      }
    }
  }
}

TEST(Grading, PanelsOutsideTheDraftArePositionedAndMovedBack) {
  drafts::Pattern src = sourceDress();
  auto inPlace = gradePattern(src, body("77"));
  ASSERT_TRUE(inPlace.ok());
  // The same design laid out 300 cm to the right: positioned by bounding boxes, graded, moved back.
  drafts::Pattern moved = src;
  for (auto& panel : moved.panels) {
    auto pts = flattenPanel(panel);
    for (auto& q : pts)
      q.x() += 300;
    unflattenPanel(pts, panel);
  }
  auto g = gradePattern(moved, body("77"));
  ASSERT_TRUE(g.ok()) << g.error().message;
  for (std::size_t i = 0; i < src.panels.size(); ++i) {
    const auto a = flattenPanel(inPlace->panels[i]);
    const auto b = flattenPanel(g->panels[i]);
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_TRUE(b[k].allFinite());
      // Alignment by box centres differs from the original placement only by the shift between
      // the design's box and the draft's; the graded shape must stay close to the in-place one.
      EXPECT_LT(std::abs((b[k] - a[k]).x() - 300), 2.0) << src.panels[i].name;
    }
  }
}

TEST(Grading, EveryCoordinateMethodGradesOrNamesTheProblem) {
  const drafts::Pattern src = sourceDress();
  for (auto m : {CoordMethod::kMeanValue, CoordMethod::kTriangle, CoordMethod::kGreen,
                 CoordMethod::kWachspress}) {
    GradeOptions o;
    o.method = m;
    auto g = gradePattern(src, body("66"), o);
    if (m == CoordMethod::kWachspress) {  // the regions are concave (darts)
      ASSERT_FALSE(g.ok());
      EXPECT_NE(g.error().message.find("not convex"), std::string::npos) << g.error().message;
      continue;
    }
    ASSERT_TRUE(g.ok()) << coordMethodName(m) << ": " << g.error().message;
    for (const auto& panel : g->panels) {
      for (const auto& q : flattenPanel(panel))
        ASSERT_TRUE(q.allFinite()) << coordMethodName(m);
    }
  }
}

TEST(BaseDraft, GradesLikeLinearGradingAndReproducesAtTheSameBody) {
  const drafts::Pattern src = sourceDress();
  GradeOptions o;
  o.baseDraft = true;
  auto same = gradePattern(src, src.measurements, o);
  ASSERT_TRUE(same.ok()) << same.error().message;
  for (std::size_t i = 0; i < src.panels.size(); ++i) {
    const auto a = flattenPanel(src.panels[i]);
    const auto b = flattenPanel(same->panels[i]);
    for (std::size_t k = 0; k < a.size(); ++k)
      EXPECT_LT((a[k] - b[k]).norm(), 1e-9);
  }
  auto g77 = gradePattern(src, body("77"), o);
  ASSERT_TRUE(g77.ok()) << g77.error().message;
  // Linear in the bust: the front bodice (about a quarter of the garment) widens by about a
  // quarter of the body's 10 cm, scaled by the garment/body ratio.
  auto width = [](const drafts::Panel& p) {
    double lo = 1e9, hi = -1e9;
    for (const auto& v : p.outline) {
      lo = std::min(lo, v.x());
      hi = std::max(hi, v.x());
    }
    return hi - lo;
  };
  const double growth = width(g77->panel("bodice_front")) - width(src.panel("bodice_front"));
  EXPECT_GT(growth, 2.0);
  EXPECT_LT(growth, 3.5);
  drafts::Measurements missing = body("77");
  missing = drafts::Measurements(std::map<std::string, double>{{"bust_circ", 95}});
  auto bad = gradePattern(src, missing, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("has no"), std::string::npos) << bad.error().message;
}

TEST(Grading, BadInputGivesNamedErrorsNotNaN) {
  drafts::Pattern src = sourceDress();
  // NaN in a panel point.
  drafts::Pattern nanPanel = src;
  nanPanel.panels[0].outline[3].x() = std::numeric_limits<double>::quiet_NaN();
  auto r1 = gradePattern(nanPanel, body("66"));
  ASSERT_FALSE(r1.ok());
  EXPECT_NE(r1.error().message.find("not finite"), std::string::npos) << r1.error().message;
  // Degenerate region: all vertices collapsed onto a line.
  drafts::Pattern flat = src;
  for (auto& v : flat.regions[0].polygon)
    v.y() = 0;
  auto r2 = gradePattern(flat, body("66"));
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().message.find("zero area"), std::string::npos) << r2.error().message;
  // A panel naming a region the draft lacks.
  drafts::Pattern unknown = src;
  unknown.panels[0].draftRegions = {"cape"};
  auto r3 = gradePattern(unknown, body("66"));
  ASSERT_FALSE(r3.ok());
  EXPECT_NE(r3.error().message.find("cape"), std::string::npos);
  // A body the recipe refuses.
  drafts::Measurements absurd = body("66");
  absurd.set("bust_circ", -5);
  auto r4 = gradePattern(src, absurd);
  ASSERT_FALSE(r4.ok());
  EXPECT_NE(r4.error().message.find("target draft"), std::string::npos);
  // A panel far outside its region (1 km away) in draft coordinates: still finite.
  drafts::Pattern far = src;
  far.panels[4].notches[0].position.x() += 1e5;
  auto r5 = gradePattern(far, body("66"));
  ASSERT_TRUE(r5.ok()) << r5.error().message;
  EXPECT_TRUE(r5->panels[4].notches[0].position.allFinite());
}

}  // namespace
}  // namespace garmcap::dsw
