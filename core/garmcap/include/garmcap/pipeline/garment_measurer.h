#pragma once
// Garment measurements in cm from the garment's silhouette on the calibrated form (seed §5.2.4),
// by the hanging-depth section model documented in docs/measurement_model.md: at a form height
// h the garment's section is an ellipse as wide as its silhouette whose depth comes from the
// form (its section there, or the envelope of the sections the garment hangs from), and
// C_garment(h) = C_ref(h) * P(w, d) / P(W_ref, D_ref), where the reference section is the form's
// torso section at h (for h at or above the hip) or its hip section (below the hip: skirts and
// hems hang from the hip), C_ref its tape (convex-hull) circumference from the 3D scan and
// W_ref, D_ref its width and depth. Lengths are vertical distances between form heights; the sleeve
// is measured along the arm's axis from the shoulder tip.

#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/calib/form_view.h"

namespace garmcap::pipeline {

using FormView = calib::FormView;

struct GarmentLandmark {
  std::string name;  // "bust_left", "hem_centre", "sleeve_end_left", "crotch", ...
  cv::Point2d px;
};

struct GarmentMeasurement {
  std::map<std::string, double> measurements;  // cm; only those the type has
  std::vector<GarmentLandmark> landmarks;      // for the review overlay
  std::vector<std::string> warnings;           // measured, but with a caveat
  // A skirt's or dress's hem round where its full width ends, when its outline's hem is not
  // level (an asymmetric hem's short side ends above the centre's hem): what the skirt attribute
  // reads instead of hem_circ. nullopt for a level hem.
  std::optional<double> flareHemCircCm;
};

/// How far (cm) a reported measurement may be off: the 95th percentile (nearest rank) of the
/// absolute error on the two physical rigs pooled (tests/data/rig_physical and
/// rig_physical_torso, cloth draped by an independent solver on a full and a torso form, the form
/// registered from the bare frame; correctly typed cases only), rounded up to 0.1 cm. The bundled
/// simulator's rigs stay far inside it. docs/measurement_model.md has the table, its sample sizes
/// and the command that reproduces it. nullopt for an unknown name.
std::optional<double> measurementUncertaintyCm(const std::string& name);

/// A sleeve shorter than this (cm, from the shoulder line) is no sleeve: the cover of the arm's
/// root by a bodice's shoulder or extended armhole reads a centimetre or two.
constexpr double kSleevelessBelowCm = 2.0;

/// Measures a garment of `type` from its mask (CV_8U, non-zero = garment, the frame's size and
/// without camera roll) on the form seen through `view`. A measurement that cannot be taken (the
/// garment does not reach the height, no sleeve on a form without arms) is left out and a
/// warning says why: nothing is invented. `frameBgr`, when given, is the frame the mask was cut
/// from (CV_8UC3, the mask's size): a skirt's or dress's hem whose outline ends level is then
/// also looked at inside (a high-low hem's back shows as a dark band under its front's hem; its
/// lengths and hem are read at the front's). Throws std::invalid_argument for an unknown type, or
/// a mask or frame whose size differs from the view's.
GarmentMeasurement measureGarment(const cv::Mat& garmentMask, const FormView& view,
                                  const std::string& type, const cv::Mat& frameBgr = cv::Mat());

/// The form's torso sections the hanging-depth section model reads (docs/measurement_model.md,
/// "Section depth"): slicing the mesh costs about a millisecond a section (7 ms for the physical
/// rig's form, more for a finer mesh), so it is made once per form and shared (measureGarment
/// finds it by the form's content). Made when the calibration's context is built, so the first
/// capture after calibrating does not pay for it (issue 16: button to item within 1.5 s).
struct FormDepthTable;
std::shared_ptr<const FormDepthTable> formDepthTable(const FormView& view);

/// How far, in cm of height, the garment below the form's hip runs as two legs with the form's
/// centre line uncovered between them: pants part so, a skirt covers the centre line down to
/// its hem. Same mask contract as measureGarment.
double partedLegsCm(const cv::Mat& garmentMask, const FormView& view);

/// How far, in cm of height, the garment covers the form's centre line below the crotch, without
/// a break of more than 0.5 cm: a dress's skirt hangs across the gap between the legs, a top
/// ends above it. 0 on a form without legs or when the garment does not reach the crotch. Same
/// mask contract as measureGarment.
double coveredBelowCrotchCm(const cv::Mat& garmentMask, const FormView& view);

}  // namespace garmcap::pipeline
