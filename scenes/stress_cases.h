#pragma once
// The stability battery (issue 7): stiff and extreme cases, each with the invariants it states
// and checks after every step (scenes/stress_watch.h). Shared by tests/test_stress.cpp (pass or
// fail) and `hail-bench stress` (the table of worst values).

#include <functional>
#include <string>
#include <vector>

#include "hail/world_settings.h"
#include "scenes/stress_watch.h"

namespace hail::bench {

/// Largest worst value each invariant may reach; a negative bound is not checked.
struct StressBounds {
  double sphere_penetration = 0.05;  ///< of the smaller radius
  double ground_penetration = 0.05;  ///< of the radius
  double energy_growth = 0.01;       ///< relative mechanical energy gain (no energy input)
  double momentum_drift = -1.0;      ///< relative; checked where no external force acts
};

struct StressResult {
  std::string name, invariants;
  StressWorst worst;
  StressBounds bounds;
  std::vector<std::string> failures;  ///< one line per invariant broken; empty: passed
  double wall_s = 0;
  std::string note;  ///< what else the case measured (e.g. the velocity it expected)
  [[nodiscard]] bool passed() const { return failures.empty(); }
};

struct StressCase {
  std::string name;
  bool slow = false;  ///< long (seconds on 2 cores): `hail-bench stress` runs it, tests tag it [.slow]
  std::function<StressResult()> run;
};

/// The cases, each building its worlds with `solver` (WorldSettings::solver).
[[nodiscard]] std::vector<StressCase> stress_cases(Solver solver = Solver::Passes);

/// Fills result.failures from the worst values and the bounds.
void judge(StressResult& result);

}  // namespace hail::bench
