#include "stage_measure.h"

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <string>

#include "hem_band.h"

namespace garmcap::pipeline {
namespace {

// A skirt's or dress's hem whose outline ends level can still be a high-low hem: under its
// front's hem the inside of its back shows as a dark band across the middle, down to the back's
// edge, which the outline's lowest edge is (docs/measurement_model.md, "Hems that are not level":
// two high-low dresses on the full form, bands of 7.2 and 8.3 cm; 43 level skirts and dresses of
// five physical rigs, at most 0.6 cm). The measurer's own check (its outline) comes first.
constexpr double kHemBandCheckCm = 3.0;

void checkHemBand(const CaptureContext& ctx, const cv::Mat& frame, const cv::Mat& garment,
                  const GarmentMeasurement& gm, CaptureResult& result) {
  if (result.type != "skirt" && result.type != "dress")
    return;
  const std::string named = "hem: the hem is not level";
  if (std::any_of(result.warnings.begin(), result.warnings.end(),
                  [&](const std::string& w) { return w.rfind(named, 0) == 0; }))
    return;
  const auto hem = std::find_if(gm.landmarks.begin(), gm.landmarks.end(),
                                [](const auto& l) { return l.name == "hem_centre"; });
  if (hem == gm.landmarks.end())
    return;
  const double band = darkBandAboveHemCm(frame, garment, hem->px, ctx.view->pose().pxPerCm);
  if (band <= kHemBandCheckCm)
    return;
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(1) << named << ": a dark band " << band
      << " cm deep lies across its middle just above its lowest edge (the inside of a high-low "
         "hem's back, below its front?); its length and round are read at that lowest edge, "
         "not at the front's";
  result.warnings.push_back(msg.str());
}

}  // namespace

GarmentMeasurement measureCapturedGarment(const CaptureContext& ctx, const cv::Mat& frame,
                                          const cv::Mat& garment, const CaptureOptions& options,
                                          CaptureResult& result) {
  const GarmentMeasurement gm = measureGarment(garment, *ctx.view, result.type);
  result.measurements = gm.measurements;
  for (const auto& w : gm.warnings)
    result.warnings.push_back(w);
  checkHemBand(ctx, frame, garment, gm, result);
  if (gm.measurements.count("sleeve_length")) {
    // The measurer reads 0 where the garment's cover of the arm is the bodice's shoulder or
    // armhole, not a sleeve (garment_measurer.cpp, endsInArmhole).
    const double sl = gm.measurements.at("sleeve_length");
    const bool sleeveless = sl < kSleevelessBelowCm;
    result.attributes["sleeve"] = sleeveless ? "none" : (sl < 35.0 ? "short" : "long");
    if (sleeveless)
      result.measurements["sleeve_length"] = 0.0;
  }
  for (const auto& [name, value] : result.measurements)
    if (const auto u = measurementUncertaintyCm(name))
      result.uncertaintyCm[name] = *u;
  if (options.corrections) {
    nlohmann::json applied = {{"warnings", nlohmann::json::array()}};
    applyCorrections(*options.corrections, result.type, result.measurements, applied);
    if (applied.contains("corrections"))
      result.corrections = applied["corrections"];
    for (const auto& w : applied["warnings"])
      result.warnings.push_back(w.get<std::string>());
  }
  if (gm.measurements.count("hem_circ") && gm.measurements.count("hip_circ") &&
      result.attributes.count("skirt"))
    result.attributes["skirt"] =
        gm.measurements.at("hem_circ") > gm.measurements.at("hip_circ") + 12.0 ? "a_line"
                                                                               : "h_line";
  return gm;
}

}  // namespace garmcap::pipeline
