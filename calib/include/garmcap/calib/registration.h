#pragma once
// Registration of the dress-form model to the bare-form frame (seed §5.2.1, §5.2.4): the pose
// (px/cm in the form plane, offset, small roll; full perspective when the camera is known), the
// fit residual and the mannequin-silhouette landmark points, and the calibration JSON that
// carries them (docs/formats.md "Calibration JSON").

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "garmcap/calib/camera.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/calib/projection.h"

namespace garmcap::calib {

/// How far below the hip the frame must reach when the form leaves it at the bottom.
inline constexpr double kMinBelowHipCm = 5.0;

struct RegistrationOptions {
  /// Camera intrinsics: when set with `distanceCm`, the model is fitted in full perspective
  /// (the distance is only the starting value; scale, i.e. distance, is fitted).
  std::optional<Intrinsics> intrinsics;
  std::optional<double> distanceCm;
  int supersample = 4;  // anti-aliasing of the model silhouette
  int maxIterations = 12;
  double minIou = 0.9;  // below this the fit fails with CalibError kFitFailed
  KeyOptions key;
};

struct Registration {
  FormPose pose;
  double iou = 0;  // model vs observed silhouette (binary, alpha > 0.5)
  int iterations = 0;
  cv::Size imageSize;
  cv::Vec3b screenBgr;
  std::vector<std::pair<std::string, Eigen::Vector2d>> landmarks;  // MSLPs, image pixels
  // When the form runs out of the frame at the bottom (legs, feet, stand): the form height (cm)
  // on its axis at the frame's bottom edge. Nothing of the form below it is seen.
  std::optional<double> frameBottomCm;
  cv::Mat1b observedMask;  // for overlays
  cv::Mat1b modelMask;
};

/// Keys `emptyFrameBgr` (already undistorted when a camera model is used) and fits the form's
/// silhouette to it by moment matching: area gives the scale, the centroid the offset and the
/// principal axis the roll, iterated on the rendered model. Throws CalibError (see chroma_key.h
/// and kFitFailed). A form whose lower part leaves the frame at the bottom is fitted on what is
/// in view (the model is rendered into the same frame, so it is clipped at the same edge); it is
/// refused with kFormCutOff when the frame's bottom edge lies above the form's hip (its waist on
/// a form without hips) plus kMinBelowHipCm: the visible part must hold the shoulders, bust,
/// waist and hip widths that fix the scale.
Registration registerForm(const FormModel& form, const cv::Mat3b& emptyFrameBgr,
                          const std::string& what, const RegistrationOptions& options = {});

/// Debug overlay: the frame, observed silhouette edge (green), model silhouette edge (magenta),
/// landmarks (red dots with names).
cv::Mat3b drawOverlay(const cv::Mat3b& frameBgr, const Registration& reg);

/// Calibration JSON (docs/formats.md). `formSidecar` and `cameraJson` are recorded as paths.
struct Calibration {
  std::filesystem::path formSidecar;
  std::optional<CameraModel> camera;
  std::filesystem::path emptyFrame;
  cv::Size imageSize;
  FormPose pose;
  double iou = 0;
  std::vector<std::pair<std::string, Eigen::Vector2d>> landmarks;
  std::map<std::string, double> landmarkHeightsCm;
  std::optional<double> frameBottomCm;  // see Registration; JSON "frame_bottom_cm", else null
};
Calibration makeCalibration(const FormModel& form, const Registration& reg,
                            const std::filesystem::path& formSidecar,
                            const std::filesystem::path& emptyFrame,
                            const std::optional<CameraModel>& camera);
std::string calibrationToJson(const Calibration& c);
void writeCalibration(const std::filesystem::path& path, const Calibration& c);
/// Strict reader: throws drafts::ParseError naming the file and field.
Calibration readCalibration(const std::filesystem::path& path);
/// The same from JSON already parsed; `what` names the source in messages.
Calibration calibrationFromJson(const nlohmann::json& j, const std::string& what);

}  // namespace garmcap::calib
