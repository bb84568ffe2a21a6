#pragma once
// `hail-bench pairs`: sphere-sphere pair search microbenchmark. SIMD brute force, uniform grid,
// sort-and-sweep and sphere BVH, build + find_pairs over all rows on one thread, by sphere count
// and radius distribution; checks that all return the same pairs.

#include <string>
#include <vector>

namespace hail::bench {

/// Runs the benchmark (flags: --max N caps the sphere count, default 64000; --repeats R,
/// default 5). Returns 0, or 1 when two pair searches disagree.
int pairs_command(const std::vector<std::string>& args);

}  // namespace hail::bench
