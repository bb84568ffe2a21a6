#pragma once
// `hail-bench stress`: runs the stability battery (scenes/stress_cases.h) and prints each case,
// its invariants and the worst values measured; exit status 1 when any case fails.

#include <string>
#include <vector>

#include "hail/world_settings.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench stress`.
struct StressOptions {
  WorldSettings settings;  ///< --solver passes|soft: the solver every case runs (settings.solver)
  std::string only;        ///< --case NAME: this case alone
  bool quick = false;
  std::string json_path;
};

/// Declares stress's flags on `app`, writing `o`.
void add_stress_options(CLI::App& app, StressOptions& o);
/// Runs the battery and prints each case; the process exit status (1 if any case failed).
int stress_command(const StressOptions& o);
/// parse_command("stress", add_stress_options, args), then stress_command; 0 after --help.
int stress_command(const std::vector<std::string>& args);

}  // namespace hail::bench
