#pragma once
// Always-on per-phase wall-clock timing: one steady_clock read at each end of a phase. Adds to
// its counter, so the substeps of one step sum up.

#include <chrono>

namespace hail {

class ScopedPhaseTimer {
 public:
  explicit ScopedPhaseTimer(double& milliseconds) : out_(milliseconds), start_(std::chrono::steady_clock::now()) {}
  ~ScopedPhaseTimer() {
    out_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopedPhaseTimer(const ScopedPhaseTimer&) = delete;
  ScopedPhaseTimer& operator=(const ScopedPhaseTimer&) = delete;

 private:
  double& out_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace hail
