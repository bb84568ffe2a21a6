#pragma once
// `hail-bench pairs`: sphere-sphere pair search microbenchmark. SIMD brute force, uniform grid,
// sort-and-sweep and sphere BVH, build + find_pairs over all rows on one thread, by sphere count
// and radius distribution; checks that all return the same pairs.

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench pairs`.
struct PairsOptions {
  int max_n = 64000;  ///< --max N caps the sphere count
  int repeats = 5;
};

/// Declares pairs' flags on `app`, writing `o`.
void add_pairs_options(CLI::App& app, PairsOptions& o);
/// Runs the benchmark and prints its table; 0, or 1 when two pair searches disagree.
int pairs_command(const PairsOptions& o);
/// parse_command("pairs", add_pairs_options, args), then pairs_command; 0 after --help.
int pairs_command(const std::vector<std::string>& args);

}  // namespace hail::bench
