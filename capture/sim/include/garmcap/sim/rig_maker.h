#pragma once
// `garmcap rig make`: renders a whole rig (ARCHITECTURE.md "Rig case") with the scene
// simulator. The rig format and its reader are capture's (garmcap/capture/rig.h); making one
// needs the simulator, the form generator and the size charts, so it lives here.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "garmcap/calib/form_model.h"
#include "garmcap/capture/rig.h"
#include "garmcap/sim/form_generator.h"

namespace garmcap::sim {

struct RigMakeOptions {
  int count = 12;
  std::uint64_t seed = 1;
  cv::Size size{960, 1280};
  double hardFraction = 0.3;
  std::string
      chart;  // size chart the garments are drafted from (randomScene); empty = sampled ease
  /// With `chart`: the kind of parametric form each size is rendered on.
  FormKind formKind = FormKind::kMannequin;
  capture::RigImageOptions images;  // how the frames are stored (recorded in rig.json)
  /// Called after each case with (index, count, case id).
  std::function<void(int, int, const std::string&)> progress;
};

/// Renders a rig: `count` scenes with a balanced mix of types (cycling top, dress, skirt,
/// pants; no pants on a form without legs), the rest drawn from the seed; writes the case folders
/// and rig.json. Returns the rig as capture::readRig would. With `options.chart`, each case is a
/// size of the chart drawn from its seed: it is rendered on the parametric form of that size's body
/// (sim::ParametricForm, written once per size to `outDir`/forms/<chart>_<size>/form.{obj,json};
/// `form` is not used) wearing the garment drafted for the same body (randomScene with chartSize).
capture::Rig makeRig(const calib::FormModel& form, const std::string& formPath,
                     const std::filesystem::path& outDir, const RigMakeOptions& options);

}  // namespace garmcap::sim
