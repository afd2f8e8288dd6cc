#pragma once
// Published size charts as full Measurements per size.

#include <string>
#include <vector>

#include "garmcap/drafts/measurements.h"

namespace garmcap::drafts {

struct SizeChart {
  std::string name;     // "korean_women", ...
  std::string source;   // where the numbers come from, and how missing ones were completed
  std::vector<std::string> sizes;  // smallest to largest, e.g. {"44","55","66","77","88"}
  std::vector<Measurements> bodies;  // one per size, same order
  const Measurements& body(const std::string& size) const;  // throws naming chart and size
};

/// All charts built into the station.
const std::vector<SizeChart>& sizeCharts();
/// Throws std::invalid_argument listing the known charts when `name` is unknown.
const SizeChart& sizeChart(const std::string& name);

}  // namespace garmcap::drafts
