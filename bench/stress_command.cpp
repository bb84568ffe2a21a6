#include "stress_command.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "scenes/machine_info.h"
#include "scenes/output_file.h"
#include "scenes/stress_cases.h"

namespace hail::bench {

int stress_command(const StressOptions& o) {
  const std::string& only = o.only;
  const bool quick = o.quick;
  const std::string& json_path = o.json_path;
  check_output_paths({json_path});
  const std::vector<StressCase> cases = stress_cases(o.solver);
  std::printf("hail-bench stress: the stability battery (%s, %s), solver %s\n", cpu_model().c_str(),
              simd_path().c_str(), o.solver == Solver::SoftStep ? "soft" : "passes");
  std::printf(
      "  bounds unless a case says otherwise: penetration 5%% of the (smaller) radius, mechanical energy gain 1%%,\n"
      "  no NaN, no centre below the terrain surface; worst values over every step\n\n");
  std::printf("  %-26s %-6s %7s %6s %9s %9s %10s %10s %7s\n", "case", "result", "steps", "NaN", "below", "pen. sph",
              "pen. gnd", "energy +", "s");
  int failed = 0, ran = 0;
  nlohmann::json out = nlohmann::json::array();
  for (const StressCase& c : cases) {
    if (!only.empty() && c.name != only) continue;
    if (quick && c.slow) continue;
    const StressResult r = c.run();
    ++ran;
    const StressWorst& w = r.worst;
    std::printf("  %-26s %-6s %7d %6zu %9zu %9.3g %10.3g %10.3g %7.2f\n", r.name.c_str(), r.passed() ? "ok" : "FAIL",
                w.steps, w.non_finite, w.below_surface, w.sphere_penetration, w.ground_penetration, w.energy_growth,
                r.wall_s);
    std::printf("      %s\n", r.invariants.c_str());
    if (!r.note.empty()) std::printf("      %s\n", r.note.c_str());
    for (const std::string& f : r.failures) std::printf("      FAILED: %s\n", f.c_str());
    std::fflush(stdout);
    failed += r.passed() ? 0 : 1;
    out.push_back({{"case", r.name},
                   {"invariants", r.invariants},
                   {"passed", r.passed()},
                   {"steps", w.steps},
                   {"non_finite", w.non_finite},
                   {"below_surface", w.below_surface},
                   {"sphere_penetration", w.sphere_penetration},
                   {"ground_penetration", w.ground_penetration},
                   {"energy_growth", w.energy_growth},
                   {"momentum_drift", w.momentum_drift},
                   {"wall_s", r.wall_s},
                   {"note", r.note},
                   {"failures", r.failures}});
  }
  if (ran == 0) throw std::invalid_argument("--case " + only + " is a slow case: run it without --quick");
  std::printf("\n  %d of %d cases passed\n", ran - failed, ran);
  if (!json_path.empty()) write_file_atomically(json_path, [&](std::ostream& file) { file << out.dump(2) << "\n"; });
  return failed == 0 ? 0 : 1;
}

}  // namespace hail::bench
