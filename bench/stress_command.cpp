#include "stress_command.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "cli.h"
#include "scenes/machine_info.h"
#include "scenes/output_file.h"
#include "scenes/setting_text.h"
#include "scenes/stress_cases.h"
#include "setting_flags.h"

namespace hail::bench {

int stress_command(const StressOptions& o) {
  const std::string& only = o.only;
  const bool quick = o.quick;
  const std::string& json_path = o.json_path;
  check_output_paths({json_path});
  const std::vector<StressCase> cases = stress_cases(o.settings.solver);
  std::printf("hail-bench stress: the stability battery (%s, %s), solver %s\n", cpu_model().c_str(),
              simd_path().c_str(), setting_text(o.settings, "solver").c_str());
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

// The flags of `hail-bench stress` (bench/cli.h's rules).

void add_stress_options(CLI::App& app, StressOptions& o) {
  std::vector<std::string> names;
  for (const StressCase& c : stress_cases()) names.push_back(c.name);
  app.description("the stability battery: each stiff or extreme case with its invariants; exit status 1 if any fails");
  // A misspelt case name is refused before the header, naming the cases there are.
  app.add_option("--case", o.only, "run this case alone")->check(CLI::IsMember(names))->type_name("NAME");
  app.add_flag("--quick", o.quick, "skip the slow cases");
  add_setting_flags(app, o.settings, {"solver"});
  app.add_option("--json", o.json_path, "every case's worst values as JSON")->type_name("FILE");
}

int stress_command(const std::vector<std::string>& args) {
  const std::optional<StressOptions> parsed = parse_command("stress", add_stress_options, args);
  return parsed ? stress_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
