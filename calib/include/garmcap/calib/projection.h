#pragma once
// Drawing the dress form into an image: the pose of the form in the camera picture and the
// projected silhouette. Registration fits a FormPose to the bare-form frame; the scene simulator
// (capture/, helper "sim") reuses the same API to draw the form, so a simulated scene and the
// calibration agree by construction.
//
// World: the form mesh in cm, y up, facing +z (towards the camera). Image: x right, y down, in
// pixels, pixel centres at integer coordinates. World +x maps to image +x.
//
// Orthographic (no intrinsics):   p = offsetPx + R(rollRad) * pxPerCm * (x, -y)
// Perspective (intrinsics given): the camera sits at distance D = fx / pxPerCm in front of the
//   plane z = 0 (through the form's axis), looking along -z, and
//   q = (cx + fx (x - Xc) / (D - z),  cy - fy (y - Yc) / (D - z)),
//   with (Xc, Yc) chosen so that the world origin lands on offsetPx; then
//   p = offsetPx + R(rollRad) (q - offsetPx).
//   So pxPerCm is the scale in the form plane z = 0 in both models, and a point in front of
//   that plane (z > 0, the bust) appears larger, as in a photograph.
//
// Typical use in the simulator:
//   FormPose pose; pose.pxPerCm = 4.0; pose.offsetPx = {1000, 1900};  // feet near the bottom
//   cv::Mat1b mask = renderSilhouette(form.mesh(), pose, {2000, 2000}, 4);
//   auto e = silhouetteEdges(form, pose, form.landmarks().waist.value());

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/mesh.h"

namespace garmcap::calib {

/// Pinhole intrinsics in pixels (distortion is handled by undistorting the frame first).
struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

struct FormPose {
  double pxPerCm = 1.0;                   // scale in the form plane z = 0
  Eigen::Vector2d offsetPx = {0, 0};      // image position of the world origin (x=0,y=0,z=0)
  double rollRad = 0;                     // in-image rotation, counter-clockwise on screen
  std::optional<Intrinsics> perspective;  // full perspective when set
  /// Camera distance to the plane z = 0 in cm (perspective only): fx / pxPerCm.
  std::optional<double> distanceCm() const;
};

/// Projects one world point (cm) to image pixels.
Eigen::Vector2d projectPoint(const FormPose& pose, const Eigen::Vector3d& worldCm);

/// Renders the silhouette of `mesh` (cm) as a 0/255 mask of `size`: a pixel is set when its
/// centre is covered (half-open edges, so shared triangle edges neither gap nor overlap, and the
/// mask has no dilation bias). The rasteriser works in double precision; `subpixelBits` is
/// ignored and kept only for source compatibility. Parts outside the image are clipped.
cv::Mat1b renderSilhouette(const TriMesh& mesh, const FormPose& pose, cv::Size size,
                           int subpixelBits = 4);

/// As renderSilhouette but anti-aliased: coverage in 0..1 estimated with `supersample`²
/// samples per pixel (the simulator composites with it; registration fits against it).
cv::Mat1f renderCoverage(const TriMesh& mesh, const FormPose& pose, cv::Size size,
                         int supersample = 4);

/// Left and right silhouette edge of the torso at one world height, in image pixels: the
/// extreme projections of the torso section's points (so in perspective they are the tangent
/// points). Arms are not part of it. std::nullopt when the form has no section at that height.
struct SilhouetteEdges {
  Eigen::Vector2d left, right;  // image points; left has the smaller image x when roll = 0
  Eigen::Vector2d centreFront;  // projection of the front-most point of the section near x=axis
};
std::optional<SilhouetteEdges> silhouetteEdges(const FormModel& form, const FormPose& pose,
                                               double heightCm);

/// The mannequin-silhouette landmark points (MSLPs, seed §5.2.4) in image pixels: for each
/// landmark height the form has, "<name>_left", "<name>_right" and "<name>_centre" points.
std::vector<std::pair<std::string, Eigen::Vector2d>> landmarkPoints(const FormModel& form,
                                                                    const FormPose& pose);

}  // namespace garmcap::calib
