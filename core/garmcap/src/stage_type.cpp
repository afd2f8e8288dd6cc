#include "stage_type.h"

#include <string>

namespace garmcap::pipeline {
namespace {

// Below the hip, pants part into legs for at least this long (the shortest shorts' inseam).
constexpr double kPartedLegsCm = 5.0;
// A dress's skirt covers the centre line at least this far below the crotch (the shortest
// dress the type database draws ends 4 cm below it on the bundled form).
constexpr double kSkirtBelowCrotchCm = 3.0;

}  // namespace

double classifyGarment(const CaptureContext& ctx, const cv::Mat& garmentW, const cv::Mat& garment,
                       CaptureResult& result) {
  const FormView& view = *ctx.view;
  const Classification cls = ctx.classifier->classify(garmentW, MatchMethod::kIou);
  result.type = cls.type;
  result.attributes = cls.attributes;
  result.confidence = cls.confidence;
  result.runnerUp = cls.runnerUp;
  // Skirt or pants: shape similarity confuses a short pair of pants with a skirt of its length
  // (and a form-coloured skirt, cut less cleanly, with pants); legs that part below the crotch
  // decide it.
  if (cls.type == "skirt" || cls.type == "pants") {
    const bool pants = partedLegsCm(garment, view) >= kPartedLegsCm;
    const std::string decided = pants ? "pants" : "skirt";
    if (decided != result.type) {
      result.warnings.push_back("type: the silhouette is closest to " + result.type + ", but it " +
                                (pants ? "parts into two legs" : "does not part into legs") +
                                "; taken for " + decided);
      result.runnerUp = result.type;
      result.type = decided;
      if (pants)
        result.attributes.erase("skirt");
      else
        result.attributes["skirt"] = "h_line";  // a_line or h_line from the hem below
    }
  }
  // Top or dress: a dress's skirt hangs across the gap between the legs below the crotch; a
  // garment that ends at the crotch is a top, however its outline compares (a top's hem near the
  // crotch, with what is left of its shadow in the gap, matched short dresses on a physical rig).
  if (result.type == "dress" && view.crotchCm() &&
      coveredBelowCrotchCm(garment, view) < kSkirtBelowCrotchCm) {
    result.warnings.push_back(
        "type: the silhouette is closest to dress, but it ends at the crotch; taken for top");
    result.runnerUp = "dress";
    result.type = "top";
    result.attributes.erase("skirt");
  }
  return cls.bestScore;
}

}  // namespace garmcap::pipeline
