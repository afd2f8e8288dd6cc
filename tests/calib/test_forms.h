#pragma once
// Shared fixtures of the calib tests: body measurements of Table 4.2 (seed) and the forms built
// from them, cached because building and analysing a form takes a fraction of a second.

#include <filesystem>
#include <map>
#include <string>

#include "garmcap/calib/form_model.h"
#include "garmcap/sim/form_generator.h"

namespace garmcap::calib::test {

// Table 4.2 of the seed, size 55 (source body) and sizes 44 and 77 (targets), Valentina names.
inline drafts::Measurements table42(const std::string& size) {
  static const std::map<std::string, std::map<std::string, double>> kSizes = {
      {"44",
       {{"height", 169.5},
        {"bust_circ", 80},
        {"waist_circ", 60},
        {"hip_circ", 85},
        {"neck_back_to_waist_b", 38.4},
        {"bustpoint_to_bustpoint", 16.4},
        {"bustpoint_to_neck_side", 23.2},
        {"waist_to_hip_b", 18.4},
        {"arm_shoulder_tip_to_wrist", 56.4},
        {"arm_wrist_circ", 19.4}}},
      {"55",
       {{"height", 171},
        {"bust_circ", 85},
        {"waist_circ", 65},
        {"hip_circ", 90},
        {"neck_back_to_waist_b", 39},
        {"bustpoint_to_bustpoint", 17},
        {"bustpoint_to_neck_side", 24},
        {"waist_to_hip_b", 19},
        {"arm_shoulder_tip_to_wrist", 57},
        {"arm_wrist_circ", 20}}},
      {"77",
       {{"height", 174},
        {"bust_circ", 95},
        {"waist_circ", 75},
        {"hip_circ", 100},
        {"neck_back_to_waist_b", 40.2},
        {"bustpoint_to_bustpoint", 18.2},
        {"bustpoint_to_neck_side", 25.6},
        {"waist_to_hip_b", 20.2},
        {"arm_shoulder_tip_to_wrist", 58.2},
        {"arm_wrist_circ", 21.2}}},
  };
  return drafts::Measurements(kSizes.at(size));
}

inline const FormModel& parametricForm55() {
  static const FormModel form = [] {
    const sim::ParametricForm pf(table42("55"));
    return FormModel(pf.mesh(), pf.sidecar("size55.obj"));
  }();
  return form;
}

inline std::filesystem::path realFormSidecar() {
  return std::filesystem::path(GARMCAP_SHARED_DIR) / "data/forms/garmentcode_mean_female/form.json";
}

inline const FormModel& realForm() {
  static const FormModel form = FormModel::load(realFormSidecar());
  return form;
}

}  // namespace garmcap::calib::test
