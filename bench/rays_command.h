#pragma once
// `hail-bench rays`: World::raycast_batch's throughput (rays per second) against a brute-force
// loop over every sphere and plane, by sphere count, with the build time of the query BVH and
// the number of rays whose hit differs from the brute force's.

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench rays`.
struct RaysOptions {
  std::string sizes = "1000,16000,64000";  ///< sphere counts, comma-separated
  int rays = 16384;                        ///< rays per batch
  int threads = 2;
  int repeats = 5;
  /// The brute force tests rays x spheres pairs: it gets at most this many pairs' worth of rays
  /// (at least 64), so that 1M spheres do not take hours; its rate and mismatches are over those.
  long long brute_budget = 400'000'000;
};

/// Declares rays' flags on `app`, writing `o`.
void add_rays_options(CLI::App& app, RaysOptions& o);
/// Runs and prints the table; 0, or 1 if any ray's hit differs from the brute force's.
int rays_command(const RaysOptions& o);
/// parse_command("rays", add_rays_options, args), then rays_command; 0 after --help.
int rays_command(const std::vector<std::string>& args);

}  // namespace hail::bench
