#include "garmcap/daemon/stage_progress.h"

#include <algorithm>

namespace garmcap::daemon {
namespace {

// Stage times of a simulated-station capture (960x1280) measured on the 2-core reference machine
// under load (result.json timings, 2026-12-03). Only the shares matter, and they move to this
// station's own after its first captures.
const std::vector<std::pair<std::string, double>> kReferenceMs = {
    {"context", 1},  {"registration", 690}, {"masks", 540}, {"grabcut", 310}, {"type", 6},
    {"measure", 11}, {"pattern", 5},        {"images", 10}, {"texture", 17},
};

// Later captures weigh this much: a few captures adapt the shares, one odd capture does not.
constexpr double kLearnRate = 0.3;

}  // namespace

StageProgress::StageProgress() {
  for (const auto& [stage, ms] : kReferenceMs) {
    order_.push_back(stage);
    meanMs_[stage] = ms;
  }
}

StageProgress::Step StageProgress::after(const std::string& stage) const {
  std::lock_guard lock(mutex_);
  double total = 0;
  for (const auto& s : order_)
    total += meanMs_.at(s);
  const auto at = std::find(order_.begin(), order_.end(), stage);
  if (at == order_.end() || total <= 0)
    return {0, ""};
  double done = 0;
  for (auto it = order_.begin(); it != at + 1; ++it)
    done += meanMs_.at(*it);
  return {std::clamp(done / total, 0.0, 1.0), at + 1 == order_.end() ? "" : *(at + 1)};
}

void StageProgress::learn(const std::vector<std::pair<std::string, double>>& timingsMs) {
  std::vector<std::string> order;
  std::map<std::string, double> ms;
  for (const auto& [stage, t] : timingsMs) {
    if (!(t >= 0))
      continue;
    if (!ms.count(stage))
      order.push_back(stage);
    ms[stage] += t;
  }
  if (order.empty())
    return;
  std::lock_guard lock(mutex_);
  for (const auto& s : order) {
    const auto known = meanMs_.find(s);
    meanMs_[s] =
        known == meanMs_.end() ? ms[s] : (1 - kLearnRate) * known->second + kLearnRate * ms[s];
  }
  // A stage the station has not seen goes after the one reported before it; stages this capture
  // skipped (no texture, say) keep their place for the next capture that runs them.
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (std::find(order_.begin(), order_.end(), order[i]) != order_.end())
      continue;
    const auto prev =
        i == 0 ? order_.begin() : std::find(order_.begin(), order_.end(), order[i - 1]) + 1;
    order_.insert(prev, order[i]);
  }
}

}  // namespace garmcap::daemon
