#pragma once
// Published size charts as full Measurements per size.

#include <string>
#include <vector>

#include "garmcap/drafts/measurements.h"

namespace garmcap::drafts {

struct SizeChart {
  std::string name;    // "korean_women", ...
  std::string source;  // where the numbers come from, and how missing ones were completed
  std::vector<std::string> sizes;    // smallest to largest, e.g. {"44","55","66","77","88"}
  std::vector<Measurements> bodies;  // one per size, same order
  const Measurements& body(const std::string& size) const;  // throws naming chart and size
};

/// All charts built into the station.
const std::vector<SizeChart>& sizeCharts();
/// Throws std::invalid_argument listing the known charts when `name` is unknown.
const SizeChart& sizeChart(const std::string& name);

/// Valentina multisize measurements file (.vst, format 0.5.4, what Valentina 0.7.52 reads) of the
/// whole chart: one dimension "Size" (Valentina's dimension Y, not a body measurement) whose
/// values are the chart's sizes (numbers evenly spaced, as 44..88 or 34..48; otherwise the
/// positions 1..N), each labelled with the size's name; the middle size is the base. Every
/// measurement gets its base value, the mean step per size (`shiftA`) and a correction for
/// each size the straight line misses, so every size's body is exact. Throws
/// std::invalid_argument naming the chart and measurement when a measurement is missing in
/// some size or is unknown (see docs/exports.md).
std::string chartToVst(const SizeChart& chart);

}  // namespace garmcap::drafts
