// GarmCap on the physical rig (tests/data/rig_physical): garments draped as cloth on the form by
// Blender's cloth solver and path-traced with Cycles through a distorted perspective camera
// (capture/sim/physical, docs/physical_rig.md). Nothing of it shares code with the pipeline or
// with the scene simulator, so this is the one accuracy check the measurer cannot pass by being a
// copy of its generator. Each case's calibration.json is the station's own registration of the
// bare frame (`garmcap calibrate --camera`), never the scene's pose. Label "rig".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/capture/rig.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/garment_classifier.h"

using namespace garmcap;
namespace fs = std::filesystem;

namespace {

const fs::path kRig = fs::path(GARMCAP_TEST_DATA_DIR) / "rig_physical";

// Regression bounds: what the pipeline reaches on this rig today plus about 15 % and 0.5 cm
// (the max bounds of lengths that are one case's segmentation failure, 54 cm, plus 10 %). They
// record today's state so that a change for the worse shows; they are no acceptance. History: when
// the rig was made (41c8482) 14 of 24 types, 56 readings missing, the table in
// docs/physical_rig.md. h/acc: frames undistorted, the garment's shadow on the form left to
// GrabCut, the garment's top read beside the neck, a "dress" that ends at the crotch taken for a
// top, sleeves from the longer arm, the touching-legs crotch, the pants hem above the shadow's
// tail, the hem in perspective and skirts' shadow legs: 21 of 24 types, 27 readings missing
// (the wide pants whose legs touch down to the hem, cases 6 and 21, read as skirts: their
// readings are missing where they were 50-55 cm off). Tops and skirts now
// typed right count readings that were left out before: case_023's waist (12 cm small, as
// before, when it read as a dress), the tops' busts (3-6 cm large). h/phys15: the dark slit
// between touching legs carved out as their gap: 24 of 24 types, 12 readings missing; the five
// pants' inseams 0.37 / 0.62 cm, outseams 0.53 / 0.99, leg openings 4.81 / 6.81. Form pixels
// between garment hanging beyond both edges of the form taken for garment: 4 missing, form-coloured
// dresses keep their skirts (garment_length 3.01 / 20.67, skirt_length 0.51 / 1.08, hem 3.26
// / 10.76); bust 3.75 / 8.20 counts case_003's bust, missing before. h/acc15b: holes inside the
// form's section bridged in a circumference's run, the hem followed from a waistband just below
// the waist, the garment's top beside the neck only where its cover reaches the shoulder: 1
// reading missing (case_014's bust, its long sleeves cover the sides 8 cm below it),
// garment_length 2.28 / 20.67, bust 3.68 / 8.74 (case_019's, missing before, +2.3). h/acc15:
// the bust from the floor of its sides' offset profile below it (a fold under the armhole is
// not the bodice's side): bust 2.29 / 6.22. h/acc15c: both pants legs' openings read above the
// higher of their two hems (a shadow tail under one leg is not read as the leg): leg openings
// 4.81 / 6.81 -> 4.19 / 6.71. h/depth15: the hanging-depth section model
// (docs/measurement_model.md, "Section depth"): bust 2.29 / 6.22 -> 1.70 / 4.82, waist 2.13 / 12.00
// -> 1.29 / 10.45, hem 3.34 / 10.76 -> 1.90 / 8.87, hip 1.08 / 1.92 -> 0.72 / 2.71 (its max bound
// moved up from 2.3 to 3.1: case_001, an H-line skirt whose sides swing out at the hip, +1.4 ->
// +2.7). h/acc15c: a leg pressed against the other one read as a tube hanging from the top of
// the leg (docs/measurement_model.md, "Leg openings"): leg openings 4.19 / 6.71 -> 3.66 / 6.52;
// the bound is not tightened, the odd half got worse (case_021 +2.8 -> -4.4). h/acc15e: a column
// with garment standing above the form's shoulder line is garment down to the bust (a
// form-coloured bodice, case_003): garment_length 2.28 / 20.67 -> 0.88 / 1.63. h/legs15: a free
// leg's opening is never shallower than the form's leg seen from the side up to the knee
// (docs/measurement_model.md, "Leg openings that hang from the knee"): leg openings 3.66 / 6.52
// -> 3.19 / 6.52 (case_012 -3.1 -> -0.8). h/dress15: the six dresses re-made without the
// generator's waist hoop (docs/physical_rig.md, "Full-form dresses without the waist hoop"); the
// measurer unchanged, the new truth reads worse: waist 1.22 / 10.45 -> 1.85 / 10.45 (the woven
// sleeveless dresses 003 and 018 hang as deep as wide at the waist: -6.7 and -8.9 cm; bound 1.5 ->
// 2.2), hip 0.72 / 2.71 -> 0.96 / 3.11 (case_014 +3.1; bound 0.9 / 3.1 -> 1.1 / 3.6), bust 1.67 /
// 4.82 -> 1.84 / 5.22 (bound kept); sleeves 0.49 / 1.91 -> 0.43 / 1.58 (bound 1.2 / 2.7 -> 1.0 /
// 2.3). h/tophem15: a loose top's hem over the hip is at least as deep as the form's sections
// above it plus its stand-off under the bust (docs/measurement_model.md, "A loose top's hem"):
// cases 13 and 23, the woven tops, -4.5 and -8.9 -> -0.5 and -0.5. h/busttruth15: the
// generator's truth no longer counts sleeve cloth in the bust (the sleeved cases' bust truth
// re-settled, docs/physical_rig.md "Sleeve cloth out of the bust truth"); the measurer
// unchanged: bust 1.84 / 5.22 -> 1.55 / 4.11 (bound 2.0 / 5.5 -> 1.8 / 4.6; case_013 -0.66 ->
// +4.11, its cap sleeve read as the bodice's side). Stop 41: a free leg at least as wide as the
// form's leg is deep is no deeper than wide ("Leg openings that hang free of the ankle"): leg
// openings 3.20 / 6.52 -> 2.25 / 4.42 (case_017 +6.5 -> +1.8; bound 3.45 / 7.4 -> 2.5 / 5.3). Stop
// 42: a loose bodice's sides are fins ("A loose bodice's sides are fins"): bust 1.55 / 4.11 ->
// 0.94 / 2.21 (case_013 +4.11 -> +1.06, 023 +3.05 -> +1.67, 018 +2.97 -> +1.21; bound 1.8 / 4.6
// -> 1.1 / 2.7). Stop 43: a sleeveless bodice's waist on a form with arms shows half its ease at
// its sides ("A sleeveless bodice's waist hangs"): waist 1.85 / 10.45 -> 1.02 / 2.87 (case_023
// -10.45 -> -2.87, 018 -8.91 -> +1.67, 003 -6.74 -> +2.11; bound 2.2 / 12.0 -> 1.2 / 3.3). Stop
// 44: a free leg hangs flattened to 0.9 of its width ("A free leg hangs flattened"): leg opening
// 2.25 / 4.42 -> 1.67 / 4.42 (case_002 +1.78 -> 0.00, 017 +1.81 -> -0.66; bound 2.5 -> 2.0). Stop
// 45: lengths read in perspective at the depth they lie at ("Lengths in perspective"): a top
// beside the neck on the form's shoulder ridge, 3 cm behind the axis, a skirt's hem front at the
// hip's front: garment_length 0.92 / 1.79 -> 0.30 / 0.67 (every one had read short; bound 1.5 /
// 2.4 -> 0.5 / 1.0), skirt_length 0.53 / 1.08 -> 0.11 / 0.22 (bound 0.7 / 1.5 -> 0.3 / 0.5).
// Per measurement {mean, max} absolute error in cm.
constexpr int kMinTypesRight = 23;
constexpr int kMaxMissing = 2;
const std::map<std::string, std::pair<double, double>> kBounds = {
    {"bust_circ", {1.1, 2.7}},        {"waist_circ", {1.2, 3.3}},     {"hip_circ", {1.1, 3.6}},
    {"hem_circ", {1.45, 4.6}},        {"garment_length", {0.5, 1.0}}, {"skirt_length", {0.3, 0.5}},
    {"sleeve_length", {1.0, 2.3}},    {"outseam", {0.7, 1.2}},        {"inseam", {0.6, 1.0}},
    {"leg_opening_circ", {2.0, 5.3}},
};

// Issue 15's acceptance on a rig: type >= 95 %, every measurement mean <= 1.0 cm, max <= 3.0 cm,
// nothing missing. Printed, not asserted, until the pipeline reaches it.
constexpr double kTargetTypeShare = 0.95, kTargetMeanCm = 1.0, kTargetMaxCm = 3.0;

struct Stats {
  double sum = 0, max = 0;
  int n = 0, missing = 0;
};

}  // namespace

// The table this prints is the independent evaluation of issue 15. The bounds are a regression
// guard at what the pipeline reaches on this rig today plus a margin (docs/physical_rig.md has
// the numbers); they are far from the targets (type >= 95 %, every mean <= 1.0 cm and
// max <= 3.0 cm). A measurement the pipeline leaves out, or a case it cannot run, counts as a
// failure: dropping a hard reading must never improve the table.
TEST(PhysicalRig, AccuracyOnClothDrapedByAnIndependentSolver) {
  ASSERT_TRUE(fs::exists(kRig / "rig.json")) << "no rig at " << kRig;
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), 24u);
  pipeline::CaptureOptions opt;
  opt.makeProductImages = false;
  opt.makeTexture = false;
  std::map<std::string, Stats> stats;
  int typeOk = 0, attrOk = 0, attrN = 0, failed = 0, missing = 0;
  // Readings within the uncertainty result.json gives them, of the correctly typed readings.
  int withinUncertainty = 0, scored = 0;
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    ASSERT_TRUE(c.calibration.is_object()) << c.id << ": no calibration.json";
    const std::string truthType = c.truth.at("type");
    const auto& truthMeas = c.truth.at("measurements");
    pipeline::CaptureResult r;
    try {
      r = pipeline::runCapture(c.empty, c.dressed, c.calibration, opt);
    } catch (const std::exception& e) {
      ++failed;
      missing += static_cast<int>(truthMeas.size());
      for (const auto& [k, v] : truthMeas.items())
        ++stats[k].missing;
      std::printf("%s %-5s FAILED: %s\n", c.id.c_str(), truthType.c_str(), e.what());
      continue;
    }
    typeOk += r.type == truthType;
    for (const auto& [k, v] : c.truth.at("attributes").items()) {
      ++attrN;
      const auto it = r.attributes.find(k);
      attrOk += it != r.attributes.end() && it->second == v.get<std::string>();
    }
    std::string line;
    for (const auto& [k, v] : truthMeas.items()) {
      const auto it = r.measurements.find(k);
      Stats& s = stats[k];
      char buf[64];
      if (it == r.measurements.end() || r.type != truthType) {
        // A wrong type measures a different garment: its readings count as missing.
        ++s.missing;
        ++missing;
        std::snprintf(buf, sizeof buf, " %s=missing", k.c_str());
      } else {
        const double e = it->second - v.get<double>();
        const auto u = r.uncertaintyCm.find(k);
        EXPECT_NE(u, r.uncertaintyCm.end()) << c.id << " " << k << ": no uncertainty_cm";
        ++scored;
        withinUncertainty += u != r.uncertaintyCm.end() && std::abs(e) <= u->second;
        s.sum += std::abs(e);
        s.max = std::max(s.max, std::abs(e));
        ++s.n;
        std::snprintf(buf, sizeof buf, " %s%+.1f", k.c_str(), e);
      }
      line += buf;
    }
    std::printf("%s %-5s as %-7s%s\n", c.id.c_str(), truthType.c_str(), r.type.c_str(),
                line.c_str());
  }
  const int n = static_cast<int>(rig.cases.size());
  std::printf(
      "physical rig: %d of %d types, attributes %d of %d, %d cases failed, %d readings "
      "missing\n",
      typeOk, n, attrOk, attrN, failed, missing);
  std::printf("%-18s %6s %6s %4s %7s\n", "measurement", "mean", "max", "n", "missing");
  for (const auto& [k, s] : stats)
    std::printf("%-18s %6.2f %6.2f %4d %7d\n", k.c_str(), s.n ? s.sum / s.n : 0.0, s.max, s.n,
                s.missing);

  bool targetsMet = typeOk >= kTargetTypeShare * n && missing == 0;
  for (const auto& [k, st] : stats)
    targetsMet = targetsMet && st.n > 0 && st.sum / st.n <= kTargetMeanCm && st.max <= kTargetMaxCm;
  std::printf("issue 15 targets (type >= 95 %%, mean <= 1.0 cm, max <= 3.0 cm, none missing): %s\n",
              targetsMet ? "met" : "NOT met");

  // result.json's uncertainty_cm claims 95 %; this rig is one of the nine it is pooled from.
  std::printf("within uncertainty_cm: %d of %d readings\n", withinUncertainty, scored);
  EXPECT_GE(withinUncertainty, 0.95 * scored);

  // Regression guard (see the comment above): today's figures plus a margin.
  EXPECT_EQ(failed, 0);
  EXPECT_GE(typeOk, kMinTypesRight);
  EXPECT_LE(missing, kMaxMissing);
  for (const auto& [k, s] : stats) {
    ASSERT_GT(s.n, 0) << k << ": never measured";
    const auto bound = kBounds.find(k);
    ASSERT_NE(bound, kBounds.end()) << k << ": no bound for this measurement";
    EXPECT_LE(s.sum / s.n, bound->second.first) << k << " mean";
    EXPECT_LE(s.max, bound->second.second) << k << " max";
  }
}

// Every reference garment of the classifier is drawn on the form as each case registers it: a
// reference that could not be drawn used to be dropped silently (the long tops reached below the
// crotch on every form; on cases 12-17 the long-sleeved ones were longer than the arm as seen), so
// a type or cut could vanish from the classifier. It is an error now; here the count is held.
TEST(PhysicalRig, EveryClassifierReferenceIsDrawnOnTheRegisteredForm) {
  const auto rig = capture::readRig(kRig);
  // 3 lengths x (3 tops, 6 dresses, 2 skirts, 1 pants): the form has arms and legs.
  constexpr std::size_t kReferences = 36;
  for (std::size_t i : {0u, 6u, 12u, 13u, 17u, 23u}) {
    ASSERT_LT(i, rig.cases.size());
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    const auto ctx = pipeline::buildCaptureContext(c.calibration, pipeline::kDefaultSizeChart);
    EXPECT_EQ(ctx->classifier->size(), kReferences) << c.id;
  }
}

namespace {

pipeline::CaptureResult runRigCase(const capture::RigCase& c) {
  pipeline::CaptureOptions opt;
  opt.makeProductImages = false;
  opt.makeTexture = false;
  return pipeline::runCapture(c.empty, c.dressed, c.calibration, opt);
}

double errorCm(const pipeline::CaptureResult& r, const capture::RigCase& c,
               const std::string& name) {
  const auto it = r.measurements.find(name);
  if (it == r.measurements.end())
    return 1e9;  // missing: fails any bound
  return std::abs(it->second - c.truth.at("measurements").at(name).get<double>());
}

// The cases of a small rig of tests/data beside the full one; fails the test when it does not
// hold `count` of them.
std::vector<capture::RigCase> casesOf(const std::string& rigName, std::size_t count) {
  const auto rig = capture::readRig(fs::path(GARMCAP_TEST_DATA_DIR) / rigName);
  EXPECT_EQ(rig.cases.size(), count) << rigName;
  std::vector<capture::RigCase> cases;
  for (const auto& info : rig.cases)
    cases.push_back(capture::loadRigCase(info.dir));
  return cases;
}

// |error| of the leg opening of the full rig's case `index`, a pants case of leg style `style`
// (a case that is not fails the test).
double legOpeningErrorCm(std::size_t index, const std::string& style) {
  const auto rig = capture::readRig(kRig);
  EXPECT_GT(rig.cases.size(), index);
  if (rig.cases.size() <= index)
    return 1e9;
  const auto c = capture::loadRigCase(rig.cases[index].dir);
  EXPECT_EQ(c.truth.at("style").value("leg", ""), style) << c.id;
  const double e = errorCm(runRigCase(c), c, "leg_opening_circ");
  std::printf("%s (%s) leg opening |error| %.2f cm\n", c.id.c_str(), style.c_str(), e);
  return e;
}

bool warnsOfSlit(const pipeline::CaptureResult& r) {
  return std::any_of(r.warnings.begin(), r.warnings.end(),
                     [](const std::string& w) { return w.find("dark slit") != std::string::npos; });
}

}  // namespace

// Wide pants whose legs touch down to the hem have no gap in their silhouette; the dark slit
// between the legs is carved out as their gap (docs/measurement_model.md, "Legs that touch").
// case_006 (checks, tuned on) and case_021 (a solid, held out) read as skirts without it. A skirt
// and two dresses hanging between the legs, one of them printed with dark dots, find no slit.
TEST(PhysicalRig, TouchingLegsArePartedByTheSlitBetweenThem) {
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), 24u);
  for (std::size_t i : {6u, 21u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "pants") << c.id;
    EXPECT_TRUE(warnsOfSlit(r)) << c.id;
    EXPECT_LE(errorCm(r, c, "inseam"), 1.0) << c.id;
    EXPECT_LE(errorCm(r, c, "outseam"), 1.2) << c.id;
  }
  for (std::size_t i : {16u, 20u, 22u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    const auto r = runRigCase(c);
    EXPECT_FALSE(warnsOfSlit(r)) << c.id;
  }
}

// A slim trouser leg hangs straight down from the kneecap in front and the calf behind, so its
// opening stands deeper than the ankle under it (the cloth solver's case_012: 12.4-13.6 cm deep
// and 11.5-11.8 wide where the form's leg is 9.9 deep); the form's section at the opening scaled
// to the leg's width read it 3.1 cm small (docs/measurement_model.md, "Leg openings that hang
// from the knee"). The straight leg case_002, whose section scaled is already deeper than the leg
// below the knee, reads as before.
TEST(PhysicalRig, ASlimLegsOpeningHangsFromTheKnee) {
  EXPECT_LE(legOpeningErrorCm(12, "slim"), 1.5);
  EXPECT_LE(legOpeningErrorCm(2, "straight"), 2.2);
}

// A straight trouser leg hanging over the ankle is a tube that clears the ankle inside it (the
// cloth solver's case_017: 15.5-16.8 cm wide and 14.0-15.3 deep at its opening, where the ankle
// is 6.5 wide and 7.6 deep). Nothing holds such a tube deeper than wide; the ankle's section
// scaled to the leg's width made it 17.9-19.2 cm deep and read it 6.5 cm large
// (docs/measurement_model.md, "Leg openings that hang free of the ankle"). The straight leg over
// the calf, case_002 (its section scaled is no deeper than wide), and the slim leg, case_012
// (held by the calf), read as before.
TEST(PhysicalRig, AStraightLegOverTheAnkleHangsFreeOfIt) {
  EXPECT_LE(legOpeningErrorCm(17, "straight"), 2.5);
  EXPECT_LE(legOpeningErrorCm(2, "straight"), 2.2);
  EXPECT_LE(legOpeningErrorCm(12, "slim"), 2.2);
}

// A dress the colour of the form matches the bare frame over large patches; where it hangs beyond
// both edges of the form, the form between is garment (docs/measurement_model.md, masks). Cases
// 3 and 7 lost their skirts without it (skirt lengths 48 and 54 cm short).
TEST(PhysicalRig, FormColouredDressesKeepTheirSkirts) {
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), 24u);
  for (std::size_t i : {3u, 7u, 22u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "dress") << c.id;
    EXPECT_LE(errorCm(r, c, "skirt_length"), 1.5) << c.id;
    EXPECT_LE(errorCm(r, c, "hip_circ"), 2.5) << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 4.5) << c.id;
  }
}

// A form-coloured bodice above the bust matches the bare frame within the noise; the cloth over
// the shoulders stands off the form by its thickness, which the screen shows, so a column whose
// shoulder line has garment above it is garment down to the bust (docs/measurement_model.md,
// masks). case_003 (a sleeveless A-line dress) read its garment length 20.7 cm short without it,
// its top at the bust; cases 7 and 22 (short sleeves) about 1 cm short either way.
TEST(PhysicalRig, FormColouredDressesKeepTheirBodices) {
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), 24u);
  for (std::size_t i : {3u, 7u, 22u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "dress") << c.id;
    EXPECT_LE(errorCm(r, c, "garment_length"), 2.0) << c.id;
  }
}

// A loose woven top's hem over the hip (docs/measurement_model.md, "A loose top's hem"): its
// sides rest on the hip like a knit's (0.7-1.0 cm off the form at the hem), but its front and back
// hang from the bust and the seat, so the hem is deeper than the form's section grown by that
// ease. Cases 13 (cap sleeves) and 23 (sleeveless), the rig's two woven tops, stand 2.75 and 3.67
// cm off the form's sides under the bust; their hems read -4.49 and -8.87 cm with the eased
// section. The rig's six knit tops (0.8-1.7 cm under the bust) must keep their hems as they read.
TEST(PhysicalRig, LooseWovenTopsHemsHangFromTheFormAbove) {
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), 24u);
  for (std::size_t i : {13u, 23u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    ASSERT_EQ(c.truth.at("garment").at("cloth").get<std::string>(), "woven") << c.id;
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "top") << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 1.5) << c.id;
  }
  for (std::size_t i : {0u, 4u, 8u, 10u, 15u, 19u}) {
    const auto c = capture::loadRigCase(rig.cases[i].dir);
    ASSERT_EQ(c.truth.at("garment").at("cloth").get<std::string>(), "knit") << c.id;
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "top") << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 1.5) << c.id;
  }
}

// The garment's shade on the form's legs below a skirt's hem is no garment (docs/
// measurement_model.md, "The garment's shadow"). tests/data/rig_physical_shade holds two A-line
// skirts rendered at 2 MP by capture/sim/physical/make_rig.py (--width 1224 --height 1632;
// case_005: --start 5 --seed 7001, a near-black brown; case_020: --start 20 --seed 7002, a mid
// red). Before the shade had to keep the form's chroma dimmed with it, the dark skirt itself
// looked like shadow, the test was switched off and the thighs in its shade parted into two
// "legs": typed pants, no skirt length or hem. The red skirt's shade on the shins touched the lit
// form only through its penumbra and was taken for garment down to 21 cm below the hem. The hem's
// height is the cloth's own (truth.json), its row the station's registration of the bare frame;
// the hem's front hangs nearer the camera and shows a few cm lower.
TEST(PhysicalRig, SkirtsShadeOnTheLegsIsNoGarment) {
  for (const auto& c : casesOf("rig_physical_shade", 2)) {
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "skirt") << c.id;
    EXPECT_LE(errorCm(r, c, "skirt_length"), 1.5) << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 4.5) << c.id;
    ASSERT_FALSE(r.silhouette.empty()) << c.id;
    const auto& pose = c.calibration.at("pose");
    const double pxPerCm = pose.at("px_per_cm").get<double>();
    const double hemRow = pose.at("offset_px").at(1).get<double>() -
                          c.truth.at("garment_heights_cm").at("hem").get<double>() * pxPerCm;
    int lowest = -1;
    for (int y = r.silhouette.rows - 1; y >= 0 && lowest < 0; --y)
      if (cv::countNonZero(r.silhouette.row(y)) > 0)
        lowest = y;
    EXPECT_LE((lowest - hemRow) / pxPerCm, 5.0) << c.id << ": garment below the hem";
  }
}

// A hem that is not level is named, as a check (docs/measurement_model.md, "Hems that are not
// level"). tests/data/rig_physical_uneven_hem holds a skirt and a dress rendered by
// capture/sim/physical/make_rig.py --hem-shape high_low (--seed 4545 --start 1 and 3; their
// backs 17 and 13 cm below their fronts) and a skirt, a skirt and a dress with --hem-shape
// asymmetric (--seed 4646, --start 5, 9 and 11; one side 8-15 cm below the other), 1224 x
// 1632, registered by the station from their bare frames. Under a high-low hem's front the
// inside of its back shows as a dark band (hem_band.h; 12.7 and 8.3 cm, where level hems show at
// most 0.6): it is named, and the centre-front lengths and the hem are read at the band's top,
// the front's hem (before stop 46 they were read to the back's edge, 7-12 cm long). The
// measurer's outline names an asymmetric hem's slant (threshold 4 cm from the level hems of five
// physical rigs, at most 2.6 cm); its centre front reads as a level one's, and its skirt
// attribute is read where its full width ends (three of the four read h_line for a_line before
// stop 46, from the round at the centre's hem, where one side has ended). The full rig's level
// hems raise no such check.
TEST(PhysicalRig, HemsThatAreNotLevelAreNamed) {
  const auto notLevel = [](const pipeline::CaptureResult& r) -> std::string {
    for (const auto& w : r.warnings)
      if (w.rfind("hem: the hem is not level", 0) == 0)
        return w;
    return "";
  };
  for (const auto& c : casesOf("rig_physical_uneven_hem", 5)) {
    const auto& g = c.truth.at("garment");
    const std::string shape = (g.contains("skirt_start") ? g.at("skirt_start") : g).at("hem_shape");
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, c.truth.at("type").get<std::string>()) << c.id;
    const std::string w = notLevel(r);
    const bool named = w.find(shape == "asymmetric" ? "slants" : "dark band") != std::string::npos;
    EXPECT_TRUE(named) << c.id << " (" << shape << "): " << (w.empty() ? "no check" : w);
    EXPECT_LE(errorCm(r, c, "skirt_length"), 1.0) << c.id;
    ASSERT_TRUE(r.attributes.count("skirt")) << c.id;
    EXPECT_EQ(r.attributes.at("skirt"), c.truth.at("attributes").at("skirt").get<std::string>())
        << c.id;
    if (r.type == "dress") {
      EXPECT_LE(errorCm(r, c, "garment_length"), 1.0) << c.id;
    }
    if (shape == "high_low") {
      EXPECT_LE(errorCm(r, c, "hem_circ"), 3.0) << c.id;
    }
  }
  const auto rig = capture::readRig(kRig);
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    const std::string type = c.truth.at("type");
    if (type != "skirt" && type != "dress")
      continue;
    EXPECT_EQ(notLevel(runRigCase(c)), "") << c.id << ": a level hem";
  }
}

// A near-black skirt's shade on the thighs is no garment (docs/measurement_model.md, "A dark
// skirt's shade on the thighs"). tests/data/rig_physical_dark_skirt holds one near-black A-line
// skirt rendered by capture/sim/physical/make_rig.py --seed 9494 --start 5 (1224 x 1632) twice:
// level, and with --hem-shape high_low, registered by the station from their bare frames. A dark
// neutral skirt over the ivory form looks like the form's shade to the chroma test, which was
// then turned off: the thighs' shade joined the skirt 7 cm down, the level hem was checked as
// "centre hangs 8.3 cm" and the high-low one, whose back hangs between the shaded thighs, read as
// pants. Now both are skirts, and the level one is measured without a check. The high-low one's
// length still reads to its back's edge between the legs (+5.0 cm): its back is as dark as its
// front, so there is no band to read its front by, and nothing names it (not asserted).
TEST(PhysicalRig, ADarkSkirtsShadeOnTheThighsIsNoGarment) {
  for (const auto& c : casesOf("rig_physical_dark_skirt", 2)) {
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "skirt") << c.id;
    if (c.id != "case_005_level")
      continue;
    for (const auto& w : r.warnings)
      EXPECT_NE(w.rfind("hem: the hem is not level", 0), 0u) << c.id << ": " << w;
    EXPECT_LE(errorCm(r, c, "skirt_length"), 1.0) << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 2.5) << c.id;
  }
}

// A knit top's shade on the form under its hem is no garment (docs/measurement_model.md, "A knit
// top's shade under its hem"). tests/data/rig_physical_hem_shade holds two knit tops rendered
// by capture/sim/physical/make_rig.py (--seed 1515 --count 1, --start 8: striped,
// sleeveless; --start 13: a cap-sleeved mid purple; 888 x 1184), registered by the station from
// their bare frames. GrabCut took the shade 1-1.5 cm down under the hem's centre for the top, the
// hem was read across it: hem 3.7 and 18.3 cm small.
TEST(PhysicalRig, KnitTopsShadeUnderTheHemIsNoGarment) {
  for (const auto& c : casesOf("rig_physical_hem_shade", 2)) {
    ASSERT_EQ(c.truth.at("garment").at("cloth").get<std::string>(), "knit") << c.id;
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "top") << c.id;
    EXPECT_LE(errorCm(r, c, "hem_circ"), 2.6) << c.id;
    EXPECT_LE(errorCm(r, c, "garment_length"), 1.5) << c.id;
  }
}

// Ten pants of a seed nothing was tuned on (tests/data/rig_physical_pants: make_rig.py --seed
// 5151 --count 1 --start K for the plan's pants K = 2, 6, 12, 17, 21, 27, 32, 36, 42, 47, 888 x
// 1184, registered by the station from their bare frames; straight, wide and slim legs in turn).
// Made at stop 41 after the free-leg rule was written, to score it and to give uncertainty_cm's
// pants readings more than the full rig's five pairs (docs/measurement_model.md, "A fresh pants
// rig"). Every case is typed pants and measured in full; the bounds are today's figures plus a
// margin, a regression guard (the pressed wide pair case_006 reads its opening 20 cm small, the
// straight checked case_032 its inseam 6.3 cm short; run from calibration.json, case_021 reads
// its waist 4.0 cm large, 2.7 under rig eval's own registration), not the targets. Stop
// 44: a free leg hangs flattened (leg opening 3.97 -> 3.25 mean, bound 4.6 -> 3.7).
TEST(PhysicalRig, FreshPantsAreTypedAndMeasuredInFull) {
  const std::map<std::string, std::pair<double, double>> bounds = {
      {"waist_circ", {0.95, 4.5}}, {"hip_circ", {0.65, 3.4}},         {"outseam", {0.75, 3.0}},
      {"inseam", {1.8, 6.8}},      {"leg_opening_circ", {3.7, 21.5}},
  };
  std::map<std::string, std::pair<double, double>> sumMax;  // per measurement: sum, max of |error|
  const auto cases = casesOf("rig_physical_pants", 10);
  for (const auto& c : cases) {
    const auto r = runRigCase(c);
    EXPECT_EQ(r.type, "pants") << c.id;
    for (const auto& [name, bound] : bounds) {
      const double e = errorCm(r, c, name);  // a missing reading fails every bound
      sumMax[name].first += e;
      sumMax[name].second = std::max(sumMax[name].second, e);
    }
  }
  for (const auto& [name, bound] : bounds) {
    EXPECT_LE(sumMax[name].first / static_cast<double>(cases.size()), bound.first) << name;
    EXPECT_LE(sumMax[name].second, bound.second) << name;
  }
}
