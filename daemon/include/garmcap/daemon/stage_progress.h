#pragma once
// Progress a person can trust for a garment capture: after each pipeline stage, the share of a
// typical capture's time that is behind us, and the stage that runs now.

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace garmcap::daemon {

/// Learns how long each pipeline stage takes on this station (a running mean over the captures
/// it ran) and turns "stage X is done" into the fraction of the capture done. Starts from the
/// durations measured on the 2-core reference machine (docs/daemon.md), so the first capture is
/// already close. Thread-safe.
class StageProgress {
 public:
  struct Step {
    double fraction = 0;  // 0..1 of the pipeline's time behind us
    std::string next;     // the stage running now ("" once the last known stage is done)
  };

  StageProgress();

  /// Where a capture stands once `stage` is done. A stage it has never seen gives {0, ""}: the
  /// caller keeps the value it had, so a bar never runs backwards.
  Step after(const std::string& stage) const;

  /// Folds one capture's stage durations (in order, as the pipeline reported them) into the
  /// means; the order becomes the one `after` assumes. A stage name reported twice (the images
  /// stage around the texture) is one stage with the durations added.
  void learn(const std::vector<std::pair<std::string, double>>& timingsMs);

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> order_;
  std::map<std::string, double> meanMs_;
};

}  // namespace garmcap::daemon
