#pragma once
// The dress form the simulator and the bundled rig use by default (../shared's GarmentCode mean
// female), for tests that render scenes: its sidecar path and the model, loaded once.

#include <string>

#include "garmcap/calib/form_model.h"

namespace garmcap::testing {

inline const std::string& bundledFormPath() {
  static const std::string path =
      std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";
  return path;
}

inline const calib::FormModel& bundledForm() {
  static const calib::FormModel form = calib::FormModel::load(bundledFormPath());
  return form;
}

}  // namespace garmcap::testing
