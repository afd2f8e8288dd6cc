#pragma once
// The scene simulator: renders the bare-form and the dressed frame of a Scene and writes the
// ground truth. Also what the "synthetic" camera back end calls to serve frames on demand.
//
//   auto form = calib::FormModel::load("form.json");
//   Scene scene = randomScene(form, "form.json", 7, {});
//   SceneRenderer r(form, scene);
//   cv::Mat empty = r.renderEmpty(), dressed = r.renderDressed();
//   writeCase(r, "rig/case_007");
//
// Threads: a SceneRenderer is immutable after construction; render calls may run concurrently.
// Errors: std::invalid_argument for a scene that cannot be drawn (garment that does not fit the
// form, too large an image), naming the reason.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/form_view.h"
#include "garmcap/capture/rig.h"
#include "garmcap/sim/scene.h"

namespace garmcap::sim {

class SceneRenderer {
 public:
  /// `form` must outlive the renderer. Validates the scene (size <= kMaxPixels, garment fits).
  SceneRenderer(const calib::FormModel& form, Scene scene);

  const Scene& scene() const { return scene_; }
  const calib::FormView& view() const { return view_; }

  /// 8-bit BGR frames of scene().size.
  cv::Mat renderEmpty() const;
  cv::Mat renderDressed() const;

  /// Garment coverage (0..1, CV_32F) in the dressed frame's geometry before shake: the exact
  /// silhouette, for tests and for IoU checks of the pipeline's segmentation.
  cv::Mat1f garmentCoverage() const;

  /// truth.json: type, attributes, measurements (cm), the form and the pose/calibration used,
  /// landmark heights, shake, fabric and lighting. See docs/simulator.md.
  nlohmann::json truth() const;

  /// The calibration the scene was rendered with, in the calibration JSON contract's terms
  /// (form model, pose, mannequin-silhouette landmark points).
  nlohmann::json calibration() const;

 private:
  cv::Mat render(bool dressed) const;

  const calib::FormModel* form_;
  Scene scene_;
  calib::FormView view_;
};

/// Writes a rig case folder: empty.png and dressed.png (or empty.jpg and dressed.jpg, as
/// `images` says; writeRigFrame, which also removes frames of the other format left from an
/// earlier run), truth.json, calibration.json (whose "empty_frame" names the file written),
/// scene.json. Throws std::invalid_argument for a JPEG quality outside 1..100.
void writeCase(const SceneRenderer& renderer, const std::filesystem::path& caseDir,
               const capture::RigImageOptions& images = {});

}  // namespace garmcap::sim
