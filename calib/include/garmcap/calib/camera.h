#pragma once
// Camera model: pinhole intrinsics and lens distortion from chessboard views (OpenCV's
// calibrateCamera), undistortion of frames, and camera.json (docs/formats.md).
// Without a camera model the station assumes an ideal pinhole camera far enough from the form
// that an orthographic projection holds (docs/calibration.md gives the error bound).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/calib/projection.h"

namespace garmcap::calib {

struct CameraModel {
  cv::Size imageSize;
  cv::Matx33d cameraMatrix = cv::Matx33d::eye();  // fx 0 cx; 0 fy cy; 0 0 1 (pixels)
  std::vector<double> distortion;                 // k1 k2 p1 p2 k3 (OpenCV order)
  double rmsPx = 0;                               // reprojection RMS of the calibration
  int views = 0;                                  // boards used
  cv::Size boardInnerCorners;                     // e.g. 9x6
  double squareMm = 0;

  Intrinsics intrinsics() const {
    return {cameraMatrix(0, 0), cameraMatrix(1, 1), cameraMatrix(0, 2), cameraMatrix(1, 2)};
  }
};

/// Calibrates from chessboard views (any channel count). Views where the board is not found are
/// skipped (their indices go to `rejected` when given). Throws CalibError kCameraCalibration when
/// fewer than 3 views are usable or the images differ in size.
CameraModel calibrateCamera(const std::vector<cv::Mat>& views, cv::Size innerCorners,
                            double squareMm, std::vector<int>* rejected = nullptr);

/// Reads every .png/.jpg/.jpeg of `dir` (sorted by name) and calibrates. Throws FileError for an
/// unreadable directory or image.
CameraModel calibrateCameraFromDirectory(const std::filesystem::path& dir, cv::Size innerCorners,
                                         double squareMm, std::vector<std::string>* rejected);

/// Undistorts a frame of the calibrated size (throws std::invalid_argument on a size mismatch).
cv::Mat undistortFrame(const cv::Mat& frame, const CameraModel& camera);

/// Undistortion of every frame of one camera: the pixel maps (cv::initUndistortRectifyMap, same
/// camera matrix for the output, as undistortFrame) are computed once, so each frame costs one
/// cv::remap. The capture pipeline keeps one per calibration and undistorts the bare and the
/// dressed frame with it, so both share the geometry the form was registered in.
class FrameUndistorter {
 public:
  explicit FrameUndistorter(const CameraModel& camera);
  /// The undistorted frame (bilinear). Throws std::invalid_argument on a size mismatch.
  cv::Mat apply(const cv::Mat& frame) const;
  cv::Size size() const { return size_; }

 private:
  cv::Size size_;
  cv::Mat map1_, map2_;  // fixed-point maps (CV_16SC2 + CV_16UC1): remap's fast path
};

std::string cameraToJson(const CameraModel& camera);
void writeCameraJson(const std::filesystem::path& path, const CameraModel& camera);
/// Strict reader: throws drafts::ParseError naming the file and the field.
CameraModel readCameraJson(const std::filesystem::path& path);
/// The same from parsed JSON; `what` names the source in messages.
CameraModel cameraFromJson(const nlohmann::json& j, const std::string& what);

}  // namespace garmcap::calib
