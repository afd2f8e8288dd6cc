#include "garmcap/sim/form_generator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "calib/test_forms.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::calib {
namespace {

// The generator is the simulator's (garmcap::sim); what it is checked with is calib's.
using sim::ParametricForm;

namespace fs = std::filesystem;

TEST(ParametricForm, MeasuredGirthsMatchInputsForSeveralSizes) {
  for (const char* size : {"44", "55", "77"}) {
    const drafts::Measurements body = test::table42(size);
    const ParametricForm pf(body);
    const TriMesh mesh = pf.mesh();
    EXPECT_EQ(openEdgeCount(mesh), 0u) << size;
    const FormModel form(mesh, pf.sidecar("f.obj"));
    for (const char* name : {"bust_circ", "waist_circ", "hip_circ", "height"}) {
      const double want = body.values().at(name);
      const double got = form.measurements().values().at(name);
      EXPECT_NEAR(got / want, 1.0, 0.005) << "size " << size << " " << name << " " << got;
    }
    // The form has all of a full mannequin's landmarks.
    const auto& l = form.landmarks();
    EXPECT_TRUE(l.crotch && l.hip && l.waist && l.bust && l.armpit && l.shoulder && l.neckBase)
        << size;
    EXPECT_NEAR(*l.crotch, pf.stationHeights().at("crotch"), 0.5) << size;
  }
}

// Acceptance: slice circumferences within 0.3% of the generator's exact girth, at random heights
// of the torso where no limb joins it.
TEST(ParametricForm, SliceGirthsWithinPointThreePercentOfExact) {
  const ParametricForm pf(test::table42("55"));
  const FormModel& form = test::parametricForm55();
  const auto& h = pf.stationHeights();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lower(h.at("crotch") + 2.5, h.at("armpit") - 3);
  double worst = 0;
  for (int i = 0; i < 60; ++i) {
    const double y = lower(rng);
    const double exact = pf.exactCircumferenceCm(y);
    const double sliced = form.section(y).circumferenceCm;
    worst = std::max(worst, std::abs(sliced / exact - 1));
    EXPECT_NEAR(sliced / exact, 1.0, 0.003) << "y " << y;
  }
  RecordProperty("worst_relative_girth_error", std::to_string(worst));
  // At the stations themselves the rings are exact.
  for (const char* s : {"hip", "waist", "bust"}) {
    EXPECT_NEAR(form.section(h.at(s)).circumferenceCm, pf.exactCircumferenceCm(h.at(s)), 1e-6);
  }
}

TEST(ParametricForm, RejectsMissingAndInconsistentMeasurements) {
  drafts::Measurements m = test::table42("55");
  drafts::Measurements noBust([&] {
    auto v = m.values();
    v.erase("bust_circ");
    return v;
  }());
  EXPECT_THROW(ParametricForm{noBust}, std::invalid_argument);
  drafts::Measurements fatWaist = m;
  fatWaist.set("waist_circ", 95);
  EXPECT_THROW(ParametricForm{fatWaist}, std::invalid_argument);
  drafts::Measurements longBack = m;
  longBack.set("neck_back_to_waist_b", 5);
  EXPECT_THROW(ParametricForm{longBack}, std::invalid_argument);
}

// The stored size-55 form (tests/data/forms/) loads through its sidecar, is small, and its
// girths are those of the korean_women chart's size 55.
TEST(ParametricForm, StoredSize55FormMatchesTheChart) {
  const fs::path sidecar = fs::path(GARMCAP_TEST_DATA_DIR) / "forms/korean_women_55.json";
  const FormModel form = FormModel::load(sidecar);
  EXPECT_LT(fs::file_size(form.sidecar().mesh), 1500u * 1000u);
  const drafts::Measurements& chart = drafts::sizeChart("korean_women").body("55");
  for (const char* name : {"bust_circ", "waist_circ", "hip_circ", "height"}) {
    EXPECT_NEAR(form.measurements().values().at(name) / chart.get(name), 1.0, 0.005) << name;
  }
}

}  // namespace
}  // namespace garmcap::calib
