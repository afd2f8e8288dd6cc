#pragma once
// Procedural fabric appearance for the scene simulator: solid, stripes, checks (gingham) and
// small prints, evaluated in garment surface coordinates (cm) so that the pattern follows the
// garment and its folds, not the image grid.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "garmcap/drafts/fabric_kind.h"

namespace garmcap::sim {

// The kinds and their names are the pipeline's vocabulary too (drafts/fabric_kind.h).
using drafts::FabricKind;
using drafts::fabricKindFromName;
using drafts::fabricKindName;

/// Colours are BGR in [0, 1] (linear-ish reflectance, before lighting).
struct Fabric {
  FabricKind kind = FabricKind::kSolid;
  cv::Vec3f base{0.5f, 0.2f, 0.2f};    // ground colour
  cv::Vec3f accent{0.9f, 0.9f, 0.9f};  // stripe / check / motif colour
  double periodCm = 2.0;               // repeat of stripes and checks, cell size of prints
  double dutyCycle = 0.4;              // fraction of the repeat that is accent (stripes, checks)
  double angleDeg = 0.0;               // stripe direction: 0 = vertical stripes
  double weaveContrast = 0.03;         // fine weave texture, relative
  double foldDepth = 0.12;             // relative shading amplitude of folds
  std::uint64_t seed = 1;              // print motif placement

  nlohmann::json toJson() const;
  /// Strict: throws drafts::ParseError naming `what` and the field.
  static Fabric fromJson(const nlohmann::json& j, const std::string& what);
};

/// Reflectance of the fabric at surface coordinates (uCm across, vCm down), without folds or
/// lighting. `footprintCm` is the size of one pixel on the fabric, used to anti-alias edges
/// of stripes and motifs (a camera integrates over the pixel).
cv::Vec3f fabricColour(const Fabric& fabric, double uCm, double vCm, double footprintCm);

/// Draws a fabric: `hard` biases towards the cases segmentation finds hard (colours near the
/// form's `formColour`, dark green-ish fabrics).
Fabric randomFabric(std::mt19937_64& rng, bool hard, const cv::Vec3f& formColour);

}  // namespace garmcap::sim
