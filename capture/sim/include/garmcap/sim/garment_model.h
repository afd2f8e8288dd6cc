#pragma once
// The garment of a simulated scene: its type, attributes and measurements (the truth the
// pipeline is judged on, names of the GarmCap pipeline issue), and how it is laid over the form
// in the image. The width model is documented in docs/simulator.md; in short, at every image
// row the garment's section hangs (a Minkowski sum of hulls of the form's sections, a uniform
// ease and segments across or front to back) and its visible width is that section's.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/calib/form_view.h"
#include "garmcap/drafts/garment_vocabulary.h"
#include "garmcap/drafts/measurements.h"

namespace garmcap::sim {

/// The types and the measurement names of truth.json: the station's vocabulary
/// (drafts/garment_vocabulary.h), which the pipeline names too.
using drafts::garmentMeasurementNames;
using drafts::garmentTypeNames;

/// The circumference is held constant this far (cm) above and below each measured height, so
/// that a reader whose landmark heights differ slightly from the simulator's still reads the
/// true value.
inline constexpr double kKnotPlateauCm = 1.5;
/// Smallest ease (garment minus form circumference) the simulator accepts at a measured height.
inline constexpr double kMinEaseCm = 2.0;

struct GarmentSpec {
  std::string type;                               // top | dress | skirt | pants
  std::map<std::string, std::string> attributes;  // sleeve: none|short|long; skirt: a_line|h_line
  std::map<std::string, double> measurements;     // cm, garmentMeasurementNames(type)
  // Shape details that are not measured (kept in truth.json under "details").
  std::string neckline = "round";  // round | v | boat
  double neckDepthCm = 8;          // centre-front neckline depth below the side neck
  double neckWidenCm = 1.5;        // neckline wider than the neck on each side
  double sleeveFlare = 1.3;        // sleeve width / arm width at the sleeve end
  double thighEase = 1.2;          // pants: thigh circumference / leg circumference
  double hemWaveCm = 0.3;          // hem undulation amplitude (zero at centre front)
  std::uint64_t foldSeed = 1;

  nlohmann::json toJson() const;
  /// Strict reader (unknown type or attribute, missing or unknown measurement): throws
  /// drafts::ParseError naming `what` and the field.
  static GarmentSpec fromJson(const nlohmann::json& j, const std::string& what);
};

/// Checks that the garment can be worn on the form in this view: every circumference at least
/// kMinEaseCm above the form's at its height, the hem above the floor and below the waist,
/// dress lengths consistent (garment_length = side neck to waist + skirt_length, within 0.5 cm),
/// pants crotch no higher than the form's and at most 8 cm below it, sleeve within the arm.
/// Throws std::invalid_argument with a sentence naming the measurement, its value and the
/// limit.
void checkGarmentFits(const GarmentSpec& spec, const calib::FormView& view);

/// Derived heights (cm) of a garment on this form: hem, top edge, pants crotch.
struct GarmentHeights {
  double topCm = 0;     // side neck (top, dress) or waist (skirt, pants)
  double hemCm = 0;     // centre-front hem
  double crotchCm = 0;  // pants only
};
GarmentHeights garmentHeights(const GarmentSpec& spec, const calib::FormView& view);

/// The garment drawn into the view's image: coverage 0..1, a shading factor (folds and the
/// garment's own roundness) and fabric surface coordinates (cm) for every covered pixel.
struct GarmentLayer {
  cv::Mat1f coverage;
  cv::Mat3f normals;    // x right, y up, z to camera
  cv::Mat1f foldShade;  // multiplicative, about 1
  cv::Mat2f uvCm;       // fabric coordinates (across, down)
};
GarmentLayer layGarment(const GarmentSpec& spec, const calib::FormView& view);

/// Garment circumference (cm) at form height h under the model (knots with plateaus).
double garmentCircAt(const GarmentSpec& spec, const calib::FormView& view, double heightCm);

}  // namespace garmcap::sim
