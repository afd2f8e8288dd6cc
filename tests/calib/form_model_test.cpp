#include "garmcap/calib/form_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "../common/temp_folder.h"
#include "garmcap/calib/errors.h"
#include "garmcap/drafts/file_io.h"
#include "test_forms.h"

namespace garmcap::calib {
namespace {

namespace fs = std::filesystem;

// One folder for the binary's files, removed when it exits.
fs::path formTempDir() {
  static const garmcap::testing::TempFolder folder("garmcap_calib_form");
  return folder.path();
}

// Acceptance: on the GarmentCode mean female body, bust, waist and hip agree with its authors'
// measurements (form.json) within 1%, with the arms kept out of the bust slice.
TEST(FormModelRealMesh, GirthsWithinOnePercentOfAuthorsValues) {
  ASSERT_TRUE(fs::exists(test::realFormSidecar())) << test::realFormSidecar();
  const FormModel& form = test::realForm();
  const auto& given = form.sidecar().measurements.values();
  for (const char* name : {"bust_circ", "waist_circ", "hip_circ"}) {
    const double derived = form.measurements().values().at(name);
    EXPECT_NEAR(derived / given.at(name), 1.0, 0.01) << name << " derived " << derived;
  }
  EXPECT_NEAR(form.heightCm(), given.at("height"), 0.05);
}

TEST(FormModelRealMesh, ArmsStayOutOfTheBustSlice) {
  const FormModel& form = test::realForm();
  const FormSection s = form.section(*form.landmarks().bust);
  EXPECT_GE(s.loopCount, 3) << "the arms are separate loops at bust height";
  EXPECT_EQ(s.torsoLoopCount, 1);
  // With the arms, the slice is far wider than the torso.
  EXPECT_GT(s.totalMaxXCm - s.totalMinXCm, s.widthCm + 20);
}

TEST(FormModelRealMesh, LandmarksOfAFullMannequinInOrder) {
  const FormLandmarks& l = test::realForm().landmarks();
  ASSERT_TRUE(l.crotch && l.hip && l.waist && l.bust && l.armpit && l.shoulder && l.neckBase);
  EXPECT_LT(*l.crotch, *l.hip);
  EXPECT_LT(*l.hip, *l.waist);
  EXPECT_LT(*l.waist, *l.bust);
  EXPECT_LT(*l.bust, *l.armpit);
  EXPECT_LT(*l.armpit, *l.shoulder);
  EXPECT_LT(*l.shoulder, *l.neckBase);
  // The sidecar's "checked" note: hips at 80-81 cm, waist at 108, bust at 121 (mesh y, cm).
  EXPECT_NEAR(*l.hip, 80.5, 2.0);
  EXPECT_NEAR(*l.waist, 108.0, 2.0);
  EXPECT_NEAR(*l.bust, 121.0, 2.0);
}

TEST(FormModelRealMesh, ProfilesAlongTheHeight) {
  const auto profile = test::realForm().profile(5.0);
  ASSERT_GT(profile.size(), 30u);
  for (const auto& s : profile) {
    if (s.torsoLoopCount == 0)
      continue;
    EXPECT_GT(s.circumferenceCm, 0);
    EXPECT_LE(s.widthCm, s.totalMaxXCm - s.totalMinXCm + 1e-9);
    // A tape around a section is at least twice its width and its depth.
    EXPECT_GE(s.circumferenceCm + 1e-6, 2 * std::max(s.widthCm, s.depthCm)) << s.heightCm;
  }
}

TEST(FormModel, FormArgumentAcceptsMeshOrSidecar) {
  const fs::path dir = test::realFormSidecar().parent_path();
  EXPECT_EQ(resolveFormSidecar(dir / "mean_female.obj"), dir / "form.json");
  EXPECT_EQ(resolveFormSidecar(dir / "form.json"), dir / "form.json");
  EXPECT_THROW(resolveFormSidecar(dir / "mean_female.yaml"), drafts::FileError);
  EXPECT_THROW(resolveFormSidecar(formTempDir() / "nothing.obj"), drafts::FileError);
}

// Writes mesh + sidecar to a temp folder and loads them; `edit` changes the sidecar.
FormModel loadWith(const TriMesh& mesh, const std::string& units,
                   const std::function<void(nlohmann::json&)>& edit) {
  const fs::path dir = formTempDir();
  writeObj(dir / "f.obj", mesh, "test");
  nlohmann::json j = {
      {"mesh", "f.obj"},
      {"mesh_units", units},
      {"units", "cm"},
      {"measurements", {{"height", 171}, {"bust_circ", 85}, {"waist_circ", 65}, {"hip_circ", 90}}}};
  edit(j);
  drafts::writeJsonFile(dir / "f.json", j);
  return FormModel::load(dir / "f.obj");
}

CalibErrorKind kindOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const CalibError& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no CalibError";
  return CalibErrorKind::kFitFailed;
}

TEST(FormModelBadInput, EachWithItsOwnError) {
  const sim::ParametricForm pf(test::table42("55"));
  const TriMesh mesh = pf.mesh(2.0, 32);
  auto none = [](nlohmann::json&) {};
  EXPECT_NO_THROW(loadWith(mesh, "cm", none));

  TriMesh open = mesh;
  open.faces.pop_back();
  EXPECT_EQ(kindOf([&] { loadWith(open, "cm", none); }), CalibErrorKind::kMeshNotClosed);

  TriMesh metres = mesh;
  metres.scale(0.01);
  EXPECT_EQ(kindOf([&] { loadWith(metres, "cm", none); }), CalibErrorKind::kMeshUnits);
  EXPECT_NO_THROW(loadWith(metres, "m", none));

  EXPECT_EQ(kindOf([&] {
              loadWith(mesh, "cm", [](nlohmann::json& j) { j["measurements"]["bust_circ"] = 88; });
            }),
            CalibErrorKind::kSidecar);
  EXPECT_NO_THROW(
      loadWith(mesh, "cm", [](nlohmann::json& j) { j["measurements"]["bust_circ"] = 86.5; }));
  EXPECT_EQ(kindOf([&] {
              loadWith(mesh, "cm", [](nlohmann::json& j) { j["landmark_heights"]["waist"] = 95; });
            }),
            CalibErrorKind::kSidecar);

  EXPECT_THROW(loadWith(mesh, "cm", [](nlohmann::json& j) { j["colour"] = "white"; }),
               drafts::ParseError);
  EXPECT_THROW(loadWith(mesh, "cm", [](nlohmann::json& j) { j.erase("mesh_units"); }),
               drafts::ParseError);
  EXPECT_THROW(loadWith(mesh, "cm", [](nlohmann::json& j) { j["mesh_units"] = "ft"; }),
               drafts::ParseError);
}

}  // namespace
}  // namespace garmcap::calib
