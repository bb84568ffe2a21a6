#pragma once
// `hail-bench scale <scene>`: the scene at doubling sphere counts and every thread count from
// 1 to the hardware's; table on stdout, CSV and JSON in a folder, plots through gnuplot.

#include <cstddef>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench scale`.
/// Largest sphere count accepted: terrain-rain holds 1.2-2.0 kB per sphere (the run's "memory"
/// line), so 8M spheres need about 10-17 GB; the memory limit stops a run before a count that
/// would not fit.
inline constexpr std::size_t kScaleMaxSpheres = 8 * 1024 * 1024;

struct ScaleOptions {
  std::string scene = "terrain-rain";
  std::size_t min_spheres = 1000, max_spheres = 256000;
  int max_threads = 0;  // 0: hardware threads
  int steps = 300;
  std::string out_dir = "hail-out/scale";
  bool no_plot = false;
  double memory_limit_gb = -1.0;  // < 0: 80% of the memory available at start; 0: no limit
};

/// Declares scale's flags on `app`, writing `o`; --min <= --max is checked once `app` is parsed,
/// and --threads 0 becomes the hardware's thread count.
void add_scale_options(CLI::App& app, ScaleOptions& o);
/// Runs every count and thread count, prints the table, writes the files; the process exit status.
int scale_command(const ScaleOptions& o);
/// parse_command("scale", add_scale_options, args), then scale_command; 0 after --help.
int scale_command(const std::vector<std::string>& args);

}  // namespace hail::bench
