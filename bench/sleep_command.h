#pragma once
// `hail-bench sleep`: what sleeping (WorldSettings::sleep) saves and what it costs in accuracy.
// Part 1 runs a scene with sleeping off and on, one after the other at each sphere count, and
// prints them side by side: ms/step, spheres asleep, and the error figures (penetration, the mean
// of each step's deepest overlap, tunnelled, fell off, kinetic energy, NaN); the share asleep
// over time goes to a CSV and a plot. Part 2 drops a sphere on a settled pile with sleeping on
// and off and compares how the pile answers against the solver's own step-to-step noise (the same
// drop one step later with sleeping off).

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench sleep`.
struct SleepOptions {
  std::string scene = "terrain-rain";
  std::string sizes = "4000";  ///< sphere counts, comma-separated; empty: part 1 is skipped
  int steps = 3600;            ///< steps per run (60 s at the scenes' 1/60 s)
  int threads = 2;
  int every = 60;  ///< steps between samples of the share asleep
  std::string out_dir = "sleep-out";
  bool no_plot = false;
  int drop_spheres = 2000;  ///< the pile of part 2 (bowl-pile); 0: part 2 is skipped
  int settle_steps = 3000;  ///< most steps the pile may take to fall asleep
  int drop_steps = 120;     ///< steps after the drop over which the pile's answer is compared
};

/// Declares sleep's flags on `app`, writing `o`.
void add_sleep_options(CLI::App& app, SleepOptions& o);
/// Runs both parts and prints their tables; 0, 1 if the drop part found the pile did not sleep,
/// 3 if a run ended with NaN.
int sleep_command(const SleepOptions& o);
/// parse_command("sleep", add_sleep_options, args), then sleep_command; 0 after --help.
int sleep_command(const std::vector<std::string>& args);

}  // namespace hail::bench
