#pragma once
// The dress form as the scene simulator sees it in one camera pose: the anti-aliased silhouette,
// per-pixel surface normals for shading, and the image-space geometry the garment model needs
// (torso edges per image row, each leg's edges and circumference, arm axes, shoulder tips, side
// neck). Built on calib's FormModel and projection so that a simulated scene and the
// calibration agree by construction.

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/projection.h"

namespace garmcap::calib {

/// Image-space cross-section of the form at one image row: left/right edge x (px) of the torso
/// (or of one leg) and its circumference in cm (convex hull of the section, a tape measure).
struct RowSection {
  double heightCm = 0;  // form height whose section projects onto this row
  double leftPx = 0, rightPx = 0;
  double circCm = 0;
  double widthPx() const { return rightPx - leftPx; }
  double centrePx() const { return 0.5 * (leftPx + rightPx); }
};

/// One arm in the image: its axis (unit direction pointing from the shoulder down the arm) and
/// the arm's half-width across the axis as a function of the distance along it.
struct ArmAxis {
  Eigen::Vector2d originPx;  // shoulder tip projected onto the axis: t = 0 here
  Eigen::Vector2d dir;       // unit, down the arm
  Eigen::Vector2d shoulderTipPx;
  // The underarm: the torso's edge on this side at the first row below the armpit, where the
  // arm's inner edge leaves the body (a bodice's armhole runs from the shoulder down to here).
  // nullopt when no torso row is found below the armpit.
  std::optional<Eigen::Vector2d> underarmPx;
  double tWristPx = 0;                 // t of the wrist (narrowest part of the forearm)
  double binPx = 1;                    // bin size of the tables below
  std::vector<double> halfWidthPx;     // per t bin from 0; extrapolated near the shoulder
  std::vector<double> centreOffsetPx;  // arm centre's signed offset from the axis per bin
  double t(const Eigen::Vector2d& p) const { return (p - originPx).dot(dir); }
  double d(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d r = p - originPx;
    return r.x() * dir.y() - r.y() * dir.x();
  }
  double halfWidthAt(double tPx) const;
  double centreAt(double tPx) const;
};

class FormView {
 public:
  /// Projects `form` with `pose` (roll must be 0: the renderer rolls the finished image) into
  /// an image of `size`. Throws std::invalid_argument when the form lacks the bust, waist, hip
  /// or armpit landmarks or when the form does not fit in the image.
  FormView(const FormModel& form, const FormPose& pose, cv::Size size);

  const FormModel& form() const { return *form_; }
  const FormPose& pose() const { return pose_; }
  cv::Size size() const { return size_; }

  /// Coverage 0..1 (CV_32F) and unit normals (CV_32FC3: x right, y up, z to camera) where
  /// covered.
  const cv::Mat1f& coverage() const { return coverage_; }
  const cv::Mat3f& normals() const { return normals_; }

  /// Image row of a form height (centre of the torso section's projection).
  double rowOfHeight(double heightCm) const;
  /// Form height seen at an image row (inverse of rowOfHeight).
  double heightOfRow(double row) const;

  /// Torso section projected onto row `row` (arms excluded); nullopt above the armpit's top or
  /// below the crotch.
  std::optional<RowSection> torsoAtRow(int row) const;
  /// Torso section at a form height (cm).
  std::optional<RowSection> torsoAtHeight(double heightCm) const;
  /// One leg (side 0: image-left, 1: image-right) at an image row, below the crotch.
  std::optional<RowSection> legAtRow(int row, int side) const;

  /// Landmark heights from calib (cm); throws std::logic_error if absent (checked at build).
  double bustCm() const { return bust_; }
  double waistCm() const { return waist_; }
  double hipCm() const { return hip_; }
  double armpitCm() const { return armpit_; }
  std::optional<double> crotchCm() const { return crotch_; }
  /// Side neck: the highest point of a garment's neckline (`neck_base` of calib, else the
  /// shoulder-line top). halfWidthPx is the neck's half-width there.
  double neckSideCm() const { return neckSide_; }
  double neckHalfWidthPx() const { return neckHalfWidthPx_; }
  /// Centre x of the body axis in the image (px) and the lowest covered row.
  double axisXPx() const { return axisXPx_; }
  int bottomRow() const { return bottomRow_; }
  /// Topmost covered row at or below the side neck in each image column (the shoulder line,
  /// with the head left out; size().width entries; -1 where none).
  const std::vector<int>& topOutline() const { return topOutline_; }

  /// Arms (0: image-left, 1: image-right); nullopt for an armless form.
  const std::optional<ArmAxis>& arm(int side) const {
    return arms_[static_cast<std::size_t>(side)];
  }

 private:
  void rasteriseNormals();
  void buildRowTables();
  void findArms();

  const FormModel* form_;
  FormPose pose_;
  cv::Size size_;
  cv::Mat1f coverage_;
  cv::Mat3f normals_;
  double bust_ = 0, waist_ = 0, hip_ = 0, armpit_ = 0, neckSide_ = 0;
  std::optional<double> crotch_;
  double neckHalfWidthPx_ = 0, axisXPx_ = 0;
  int bottomRow_ = 0;
  std::vector<int> topOutline_;
  // Height samples (increasing height) and their projected rows (decreasing).
  std::vector<double> sampleHeights_, sampleRows_;
  std::vector<std::optional<RowSection>> torsoRows_;
  std::array<std::vector<std::optional<RowSection>>, 2> legRows_;
  std::array<std::optional<ArmAxis>, 2> arms_;
};

}  // namespace garmcap::calib
