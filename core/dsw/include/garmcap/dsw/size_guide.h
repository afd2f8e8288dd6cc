#pragma once
// The size guide a shopper reads: one row per chart size of the garment's own measurements in
// cm, the item's row holding exactly what was measured on the item and every other row the
// item's values moved by the grading (the graded patterns' change from the item's size). Built
// in one place (buildSizeGuide) and written by one writer per format; the CLI, the daemon, the
// web UI and every shop export go through this type.
//
// Measurement names are the station's garment vocabulary (docs/formats.md): bust_circ,
// waist_circ, hip_circ, hem_circ, garment_length, skirt_length, sleeve_length, outseam, inseam,
// leg_opening_circ. Pattern-maker values (armscye, sleeve cap, neck to waist) are not shown.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/size_run.h"

namespace garmcap::dsw {

struct SizeGuideRow {
  std::string size;                         // chart size label, e.g. "55"
  std::map<std::string, double> garmentCm;  // garment measurements of this size
  std::map<std::string, double> bodyCm;     // the chart body this size is for (circumferences)
};

struct SizeGuide {
  std::string type;                       // garment type: top | dress | skirt | pants
  std::string chart;                      // size chart name, e.g. "korean_women"
  std::vector<std::string> measurements;  // column order, shopper-facing first
  std::vector<SizeGuideRow> rows;         // smallest size first
  std::size_t itemRow = 0;                // index into rows of the item's own size

  const SizeGuideRow& item() const { return rows.at(itemRow); }
  const std::string& itemSize() const { return item().size; }
};

/// Shopper-facing garment measurement names in display order.
const std::vector<std::string>& sizeGuideMeasurementNames();

/// Human label of a garment measurement ("bust_circ" -> "Bust", "leg_opening_circ" -> "Leg
/// opening"); unknown names get their words capitalised.
std::string measurementLabel(const std::string& name);

/// Garment type of a draft recipe: blouse/bodice -> top, skirt_a/skirt_h -> skirt, dress,
/// pants; std::nullopt for a recipe that is not a garment a shop sells.
std::optional<std::string> garmentTypeOfRecipe(const std::string& recipe);

/// The body a garment fits: each of bust/waist/hip circumference the garment has, minus the
/// recipe's default ease for it (a top's hem_circ stands for its hip). Circumferences only.
/// Unknown recipe: std::nullopt.
std::optional<std::map<std::string, double>> bodyFittedBy(
    const std::string& recipe, const std::map<std::string, double>& garmentCm);

/// Index of the chart size whose body is nearest (root mean square over the names both carry)
/// to `bodyCm`; std::nullopt when they share no name. The one "nearest chart size" routine.
std::optional<std::size_t> nearestChartSize(const drafts::SizeChart& chart,
                                            const std::map<std::string, double>& bodyCm);

/// The sample size of a draft: the chart size whose body is nearest (nearestChartSize) to the
/// body the draft was made for (the pattern's own measurements: the form's body for a capture),
/// by the circumferences bust, waist and hip it carries. Not the garment: its ease (whatever
/// the design chose) is not the body's. std::nullopt when the draft's body has none of the three.
std::optional<std::size_t> sampleSizeOf(const drafts::Pattern& draft,
                                        const drafts::SizeChart& chart);

/// The shopper measurements a pattern shows (drafts::measurePattern output translated to the
/// garment vocabulary: outseam_length -> outseam, a trouser's hem_circ -> leg_opening_circ, a
/// dress's length from neck to hem). Pattern-maker values are dropped.
std::map<std::string, double> shopperMeasurements(const std::string& type,
                                                  const std::map<std::string, double>& patternCm);

/// Builds the guide. `itemCm`: what was measured on the item (garment vocabulary; values <= 0,
/// such as a sleeveless top's sleeve, are left out); `itemSize`: index into `run.sizes` of the
/// item's own size. Other rows: item value + (graded value of that size - graded value of the
/// item's size); a measurement the grading does not move in a known way is shown in the item's
/// row only. Error when `itemSize` is out of range or `itemCm` has no measurement to show.
Expected<SizeGuide> buildSizeGuide(const SizeRun& run, const drafts::SizeChart& chart,
                                   const std::string& type,
                                   const std::map<std::string, double>& itemCm,
                                   std::size_t itemSize);

/// A guide of the item alone (one row), for when no graded run exists.
SizeGuide singleSizeGuide(const std::string& type, const std::string& chart,
                          const std::string& size, const std::map<std::string, double>& itemCm);

/// {"units": "cm", "type", "chart", "base_size": the item's size, "measurements": [names],
///  "rows": [{"size", "garment": {name: cm}, "body": {name: cm}}]}; cm to 0.1 mm.
std::string sizeGuideJson(const SizeGuide& guide);
/// Strict reader of sizeGuideJson's output; throws drafts::ParseError "<what>: <field>: reason".
SizeGuide sizeGuideFromJson(const std::string& text, const std::string& what);
/// `size,item,<measurement>...` (names as column heads), one row per size, "yes" in `item`
/// on the item's row, cm to 0.1; CRLF line ends, cells through csvField.
std::string sizeGuideCsv(const SizeGuide& guide);

}  // namespace garmcap::dsw
