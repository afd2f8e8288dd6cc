#include "stage_measure.h"

namespace garmcap::pipeline {

GarmentMeasurement measureCapturedGarment(const CaptureContext& ctx, const cv::Mat& frame,
                                          const cv::Mat& garment, const CaptureOptions& options,
                                          CaptureResult& result) {
  const GarmentMeasurement gm = measureGarment(garment, *ctx.view, result.type, frame);
  result.measurements = gm.measurements;
  for (const auto& w : gm.warnings)
    result.warnings.push_back(w);
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
  const auto hem = gm.flareHemCircCm ? gm.flareHemCircCm
                   : gm.measurements.count("hem_circ")
                       ? std::optional<double>(gm.measurements.at("hem_circ"))
                       : std::nullopt;
  if (hem && gm.measurements.count("hip_circ") && result.attributes.count("skirt"))
    result.attributes["skirt"] = *hem > gm.measurements.at("hip_circ") + 12.0 ? "a_line" : "h_line";
  return gm;
}

}  // namespace garmcap::pipeline
