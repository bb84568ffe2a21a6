#pragma once
// The cases with a known answer (docs/scenes.md A-D and the slope roll), each as an
// engine-neutral scene plus an observer that turns the frames it sees into one error figure.
// `hail-bench accuracy` runs them for every engine and knob at several dt.

#include <memory>
#include <string>
#include <vector>

#include "peer_engine.h"

namespace hail::bench {

class AccuracyCase {
 public:
  virtual ~AccuracyCase() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// What is measured and what the exact answer is, one line.
  [[nodiscard]] virtual std::string summary() const = 0;
  [[nodiscard]] virtual PeerScene scene() const = 0;
  /// Simulated seconds.
  [[nodiscard]] virtual double duration() const = 0;
  /// Forgets what was observed (a case object is reused across runs).
  virtual void reset() = 0;
  /// Called after every frame with the state at time t.
  virtual void observe(const std::vector<PeerState>& state, double t) = 0;
  /// Relative error against the exact answer (0 = exact; 1 = 100%).
  [[nodiscard]] virtual double error() const = 0;
};

/// A, B, C (m2 = 1 and 1000), D and the slope roll.
[[nodiscard]] std::vector<std::unique_ptr<AccuracyCase>> known_answer_cases();

}  // namespace hail::bench
