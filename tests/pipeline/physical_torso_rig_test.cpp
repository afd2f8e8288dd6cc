// GarmCap on the physical torso rig (tests/data/rig_physical_torso): a torso dress form on a stand
// cut from the physical rig's body by the physical generator itself (capture/sim/physical/
// torsoform.py: no head, no arms, no legs, a pole and a foot), dressed with sleeveless tops and
// dresses and with skirts draped by Blender's cloth solver and rendered by Cycles
// (docs/physical_rig.md, "Torso form"). It shares no code with the station or with `garmcap
// make-form --torso` / `rig make --torso`, the only other torso rigs. Each case's
// calibration.json is the station's own registration of the bare frame (`garmcap calibrate
// --camera`, capture/sim/physical/calibrate_rig.py). Nothing was tuned on this rig. Label "rig".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "garmcap/capture/rig.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"

using namespace garmcap;
namespace fs = std::filesystem;

namespace {

const fs::path kRig = fs::path(GARMCAP_TEST_DATA_DIR) / "rig_physical_torso";

// What the pipeline reaches on this rig when it was made (below), plus about 15 % and
// 0.5 cm: a regression guard, not the acceptance. Issue 15's acceptance (type >= 95 %, every
// mean <= 1.0 cm, max <= 3.0 cm, nothing missing) is printed below, met or not; the table is in
// docs/measurement_model.md, "Torso forms". Per measurement {mean, max} absolute error in cm.
// History: made and scored once at b50868b (16 cases, seed 2015): 14 of 16 types (two
// form-coloured dresses, 007 and 010, read as skirts: their bodice is lost), 19 readings missing
// (those two dresses' 12; case_015, a green-and-white striped dress on the green screen, 5; the
// two light tops 000 and 004 lose their hem), bust 3.21 / 19.58 (case_015), garment_length
// 4.65 / 15.18 and waist 2.37 / 11.65 (the light tops 000 and 004 lose their upper part and
// hem from the silhouette), hem 4.11 / 32.97 and skirt_length 5.96 / 52.02 (case_014, a
// form-coloured skirt), hip 0.88 / 1.95 (the one measurement within the bound).
// Registration: px/cm within 0.25 %.
// Re-made by h/torsogen15 (the six dresses only, same seed): the skirt's waistband had been
// pinned outside the unsettled bodice and stood 3-5 cm off the form as a hoop over the settled
// bodice (docs/physical_rig.md, "Dresses on the torso form"); the form-coloured dresses 007 and
// 010 read as skirts below it. Now 16 of 16 types, 5 readings missing (case_015's 3, the light
// tops' hems), bust 2.05 / 10.77 (case_015), garment_length 1.48 / 4.72, hem 4.45 / 32.97
// (case_014), hip 2.17 / 14.44 (case_015), skirt_length 4.93 / 52.02 (case_014), waist
// 4.75 / 12.19: every woven dress's waist reads 5.6-11.3 cm small (likely: the back of its
// undarted bodice hangs 3-4 cm off the small of the back, which the front view does not show).
// Stop 39: a garment that hugs the form passes the closure test by a pixel, row by row; rows
// between closed rows (up to 1 cm) are never sure background (stage_masks, kClosureGapCm).
// case_014's form-coloured skirt had been cut across 7 cm under its waist: hem 38.25 -> 0.47,
// skirt_length 54.45 -> 0.12. Now (this test) bust 1.29 / 2.90, garment_length 1.48 / 4.72,
// hem 1.95 / 6.44, hip 1.69 / 7.49, skirt_length 0.21 / 0.53, waist 4.79 / 12.98. Stop 42: shade
// under a top's hem darker than nearly all of the top is sure form (docs/measurement_model.md,
// "Shade under a light top's hem"): the light tops 000 and 004 keep their hems and lengths, 5 -> 3
// readings missing, garment_length 1.48 / 4.72 -> 0.69 / 1.42 (bound 2.2 / 5.9 -> 1.0 / 2.0),
// hem 1.95 / 6.44 -> 2.55 / 9.35 (bound 2.8 / 7.9 -> 3.0 / 10.3): the two hems now read are 9.4
// and 3.6 cm small, loose sleeveless wovens that hang as deep as wide (the waist's failure, at the
// hem). Also stop 42: a loose bodice's sides are fins (docs/measurement_model.md, "A loose
// bodice's sides are fins"): bust 1.29 / 2.90 -> 0.88 / 2.90 in this test (`rig eval`, which
// registers each case itself: 1.05 / 1.77 -> 0.64 / 1.49; bound 2.0 / 3.9 -> 1.0 / 3.2). Stop 43:
// a sleeveless bodice's waist on an armless form shows 0.7 of its ease at its sides ("A
// sleeveless bodice's waist hangs"): waist 4.78 / 12.98 -> 2.08 / 12.98 (bound 6.0 / 14.5 -> 2.5 /
// 14.5; the largest, case_015's -13.0, is its striped knit dress's outline lost below the bust).
// Stop 44: a dress's hem hangs from its bodice ("A dress's hem hangs from its bodice"): hem 2.55
// / 9.35 -> 2.23 / 9.35, its dresses' hems 1.1 cm larger each (bound 3.0 -> 2.4). Stop 45:
// lengths read in perspective at the depth they lie at ("Lengths in perspective"): the dresses'
// tops had read 0.6-1.0 cm low and now within 0.25 cm, their hems 0.2-0.5 cm lower than before
// (skirt_length 0.21 / 0.53 -> 0.42 / 0.68, bound 0.8 / 1.2 -> 0.6 / 1.0); garment_length
// 0.69 / 1.42 -> 0.67 / 2.34: the light woven tops 000 and 004, which read long at their hems,
// now read 2.3 and 1.5 cm long (bound 1.0 / 2.0 -> 1.0 / 2.6).
constexpr std::size_t kCases = 16;
constexpr int kMinTypesRight = 16;
constexpr int kMaxMissing = 3;
constexpr double kMaxScaleError = 0.004;
const std::map<std::string, std::pair<double, double>> kBounds = {
    {"bust_circ", {1.0, 3.2}}, {"waist_circ", {2.5, 14.5}},    {"hip_circ", {2.5, 9.1}},
    {"hem_circ", {2.4, 10.3}}, {"garment_length", {1.0, 2.6}}, {"skirt_length", {0.6, 1.0}},
};

// Issue 15's acceptance on a rig.
constexpr double kTargetTypeShare = 0.95, kTargetMeanCm = 1.0, kTargetMaxCm = 3.0;

struct Stats {
  double sum = 0, max = 0;
  int n = 0, missing = 0;
};

}  // namespace

// Readings of correctly typed cases only: a reading left out, or one of a wrong type, counts as
// missing. A sleeveless truth (sleeve_length 0) is not owed on an armless form: the station reads
// no sleeve there (docs/measurement_model.md, "Torso forms"); its sleeve attribute must say none.
TEST(PhysicalTorsoRig, AccuracyOnClothDrapedOnATorsoForm) {
  ASSERT_TRUE(fs::exists(kRig / "rig.json")) << "no rig at " << kRig;
  const auto rig = capture::readRig(kRig);
  ASSERT_GE(rig.cases.size(), kCases);
  pipeline::CaptureOptions opt;
  opt.makeProductImages = false;
  opt.makeTexture = false;
  std::map<std::string, Stats> stats;
  int typeOk = 0, attrOk = 0, attrN = 0, failed = 0, missing = 0, pants = 0;
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
      for (const auto& [k, v] : truthMeas.items()) {
        ++stats[k].missing;
        ++missing;
      }
      std::printf("%s %-5s FAILED: %s\n", c.id.c_str(), truthType.c_str(), e.what());
      continue;
    }
    typeOk += r.type == truthType;
    pants += r.type == "pants";
    for (const auto& [k, v] : c.truth.at("attributes").items()) {
      ++attrN;
      const auto it = r.attributes.find(k);
      attrOk += it != r.attributes.end() && it->second == v.get<std::string>();
    }
    std::string line;
    for (const auto& [k, v] : truthMeas.items()) {
      const auto it = r.measurements.find(k);
      char buf[64];
      if (k == "sleeve_length" && v.get<double>() == 0.0 && it == r.measurements.end()) {
        line += " sleeve_length=not-owed";
        continue;
      }
      Stats& s = stats[k];
      if (it == r.measurements.end() || r.type != truthType) {
        ++s.missing;
        ++missing;
        std::snprintf(buf, sizeof buf, " %s=missing", k.c_str());
      } else {
        const double e = it->second - v.get<double>();
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
      "physical torso rig: %d of %d types, attributes %d of %d, %d cases failed, %d readings "
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

  // No pants reference is laid on a form without legs.
  EXPECT_EQ(pants, 0);
  EXPECT_EQ(failed, 0);
  EXPECT_GE(typeOk, kMinTypesRight);
  EXPECT_LE(missing, kMaxMissing);
  for (const auto& [k, s] : stats) {
    const auto bound = kBounds.find(k);
    ASSERT_NE(bound, kBounds.end()) << k << ": no bound for this measurement";
    if (s.n == 0)
      continue;  // every reading missing: held by kMaxMissing
    EXPECT_LE(s.sum / s.n, bound->second.first) << k << " mean";
    EXPECT_LE(s.max, bound->second.second) << k << " max";
  }
}

// The station's registration of each bare frame against the scene's truth: px/cm = fx / D at the
// form's axis plane (truth.json camera), which the registration never reads.
TEST(PhysicalTorsoRig, RegistrationScaleFromTheBareFrame) {
  const auto rig = capture::readRig(kRig);
  double worst = 0;
  for (const auto& info : rig.cases) {
    const auto c = capture::loadRigCase(info.dir);
    const auto& cam = c.truth.at("camera");
    const double truth = cam.at("fx").get<double>() / cam.at("distance_cm").get<double>();
    const double read = c.calibration.at("pose").at("px_per_cm").get<double>();
    worst = std::max(worst, std::abs(read / truth - 1.0));
  }
  std::printf("registration: worst |px/cm error| %.3f %%\n", 100 * worst);
  EXPECT_LE(worst, kMaxScaleError);
}
