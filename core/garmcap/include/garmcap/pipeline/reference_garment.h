#pragma once
// The pipeline's own picture of a garment of each type on the calibrated form, for the
// classifier's reference silhouettes. It is written from what defines the types (a skirt hangs
// from the waist to a hem, straight from the hip (H) or flared (A); pants part at the crotch into
// two legs; a top or a dress covers the shoulders from a neckline and may have sleeves; a dress
// is a bodice with a skirt) and from the recipes' ease, on calib's geometry of the form. It shares
// nothing with the scene simulator's garment model (docs/architecture.md: a generator and the
// method it tests must not share a model).
//
// Width: a garment whose girth exceeds the form's by an ease e stands off the form by
// e / (2 pi) all round (the offset of a convex section by d is 2 pi d longer), so in the picture
// its outline lies that far outside the form's on either side. Below the hip a skirt no longer
// follows the body: it hangs from the hip's outline, straight or widening to its hem.

#include <map>
#include <opencv2/core.hpp>
#include <string>

#include "garmcap/drafts/measurements.h"
#include "garmcap/pipeline/garment_measurer.h"

namespace garmcap::pipeline {

struct ReferenceGarment {
  std::string type;                               // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve: none|short|long; skirt: a_line|h_line
  double topCm = 0;  // skirt, pants: the waistband's top edge (tops and dresses: the neckline)
  double hemCm = 0;  // form height of the hem at centre front (pants: of the leg hems)
  // Ease (cm of girth over the form's) at the form's bust, waist and hip; a skirt's at its hem
  // over the form's hip girth (an A-line's grows below the hip, an H-line's does not).
  double easeBustCm = 0, easeWaistCm = 0, easeHipCm = 0, easeHemCm = 0;
  double neckDepthCm = 0;  // centre-front neckline below the side neck (tops, dresses)
  double sleeveCm = 0;     // along the arm from the shoulder tip; 0 sleeveless
  double easeSleeveTopCm = 0, easeSleeveWristCm = 0;  // over the arm's girth
  double legOpeningCircCm = 0;                        // pants: girth of each leg's hem
};

/// The reference garment of `type` and `attributes` that the project's recipes draft with their
/// default ease and design, its lengths scaled by `lengthFactor` (1: the recipe's default) and
/// kept on this form (hems above the floor, a top's above the crotch, sleeves within the arm).
/// Throws std::invalid_argument for an unknown type or a missing attribute.
ReferenceGarment referenceGarment(const std::string& type,
                                  const std::map<std::string, std::string>& attributes,
                                  double lengthFactor, const drafts::Measurements& body,
                                  const FormView& view);

/// The garment's silhouette on the form as `view` sees it: CV_8U of the view's size, 255 where
/// the garment is. Throws std::invalid_argument when the form lacks what the garment needs (no
/// torso section at the armpit or hip; legs for pants) or the garment covers nothing.
cv::Mat1b drawReferenceGarment(const ReferenceGarment& garment, const FormView& view);

}  // namespace garmcap::pipeline
