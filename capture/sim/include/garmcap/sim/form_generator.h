#pragma once
// A parametric dress form: from body measurements, a smooth closed mannequin (torso with neck
// and head, arms in an A-pose, legs) whose torso girths are the inputs. Used by tests, by the
// scene simulator and wherever no scanned form is at hand.
//
// The torso is a stack of elliptical rings; its girth C(y) and depth/width ratio r(y) are
// monotone cubic (PCHIP) interpolants through stations at crotch, hip, waist, underbust, bust,
// armpit, shoulder, neck base, chin, head and crown, so a girth station that is a local extremum
// (hip, waist, bust) is exactly the extremum of C(y). Each ring polygon is scaled so that its
// perimeter is exactly C(y): slicing the mesh at a ring height returns C(y), and between rings the
// linear interpolation of two similar polygons departs from C(y) by far less than 0.1%.
// Arms and legs are separate closed tubes that start inside the torso (the mesh is closed, but
// the parts overlap rather than being boolean-united; slices there contain nested loops).
//
// The torso variant (FormKind::kTorso) is a boutique dress form: the same torso from a flat bottom
// at the body's crotch height up to a neck cap (a short neck ending flat), no head, no arms (the
// section simply closes over the shoulders, as an armhole plate does), no legs, standing on a thin
// pole with a round foot on the floor. Its landmark heights are the body's: the form stands where
// the body's torso would.

#include <map>
#include <string>
#include <vector>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/mesh.h"
#include "garmcap/drafts/measurements.h"

namespace garmcap::sim {

/// What the generator builds: a full mannequin or a torso form on a stand.
enum class FormKind { kMannequin, kTorso };

/// The stand of a torso form (cm).
inline constexpr double kTorsoPoleRadiusCm = 1.25;  // a 2.5 cm pole
inline constexpr double kTorsoFootRadiusCm = 16.0;  // the round foot on the floor
inline constexpr double kTorsoFootHeightCm = 2.0;

class ParametricForm {
 public:
  /// Required measurements: height, bust_circ, waist_circ, hip_circ. Optional (defaults are
  /// proportions of the required ones): neck_circ, arm_wrist_circ, neck_back_to_waist_b,
  /// waist_to_hip_b, leg_crotch_to_floor, shoulder_tip_to_shoulder_tip_b,
  /// arm_shoulder_tip_to_wrist, bustpoint_to_bustpoint, bustpoint_to_neck_side, and for the
  /// vertical layout height_waist_side (or leg_waist_side_to_floor) and rise_length_side.
  /// Throws std::invalid_argument naming a missing or inconsistent measurement (e.g. waist not
  /// smaller than bust and hip, landmarks out of order).
  explicit ParametricForm(const drafts::Measurements& body, FormKind kind = FormKind::kMannequin);

  FormKind kind() const { return kind_; }

  /// The mesh in cm: y up, floor at y = 0, facing +z, body axis at x = z = 0.
  /// `ringStepCm` is the vertical spacing of torso rings (limbs use 1.5x), `segments` the
  /// vertices per torso ring (limbs use half).
  calib::TriMesh mesh(double ringStepCm = 1.0, int segments = 64) const;

  /// The exact torso girth C(y) in cm (the interpolant the rings are built from); 0 outside the
  /// torso. Valid away from the shoulders, where the arm tubes join.
  double exactCircumferenceCm(double yCm) const;

  /// Station heights (cm): crotch, hip, waist, bust, armpit (approximate: where the arm tube
  /// leaves the torso), shoulder, neck_base. A torso form has the same stations (its crotch is
  /// the height of its flat bottom, not a crotch) and "top", the neck cap's.
  const std::map<std::string, double>& stationHeights() const { return heights_; }

  /// Sidecar for the generated mesh: the input measurements that the form realises and the
  /// landmark heights of bust, waist, hip and crotch (a torso form: bust, waist and hip; its
  /// "height" is the mesh's, floor to neck cap, not the body's).
  calib::FormSidecar sidecar(const std::string& meshFileName) const;

 private:
  double girthAt(double y) const;
  double ratioAt(double y) const;

  drafts::Measurements body_;
  FormKind kind_ = FormKind::kMannequin;
  std::map<std::string, double> heights_;
  std::vector<double> stY_, stC_, stR_;  // torso stations: height, girth, depth/width ratio
  double height_ = 0, crotchY_ = 0, topY_ = 0;
  double shoulderHalfWidth_ = 0, armLength_ = 0, upperArmR_ = 0, wristR_ = 0, thighR_ = 0;
  double legGap_ = 0, armAngleRad_ = 0;
};

/// Ellipse perimeter with semi-axes a, b (Ramanujan's second formula; relative error < 1e-9 for
/// b/a in 0.5..1, enough here).
double ellipsePerimeter(double a, double b);

}  // namespace garmcap::sim
