#pragma once
// Times the capture's stages one after another and reports each as it ends (internal).

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {

class StageTimer {
 public:
  using Clock = std::chrono::steady_clock;
  /// Times from `start` (the first stage began then).
  StageTimer(std::vector<StageTiming>& out, const std::function<void(const StageTiming&)>& onDone,
             Clock::time_point start = Clock::now())
      : out_(out), onDone_(onDone), start_(start) {}
  /// Ends `stage`: its time since the previous stage ended (or since construction).
  void done(const std::string& stage) {
    const auto now = Clock::now();
    out_.push_back({stage, std::chrono::duration<double, std::milli>(now - start_).count()});
    start_ = now;
    if (onDone_)
      onDone_(out_.back());
  }

 private:
  std::vector<StageTiming>& out_;
  const std::function<void(const StageTiming&)>& onDone_;
  Clock::time_point start_;
};

}  // namespace garmcap::pipeline
