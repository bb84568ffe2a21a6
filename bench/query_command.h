#pragma once
// `hail-bench query`: terrain query microbenchmark (stackless BVH walk, stack walk, brute force,
// direct grid-cell lookup) over terrain-rain's heightmap.

#include <string>
#include <vector>

#include "kernel/terrain/terrain_parts.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench query`.
struct QueryOptions {
  int queries = 100000;
  int leaf = static_cast<int>(Terrain::kDefaultLeafSize);
  int repeats = 5;
};

/// Declares query's flags on `app`, writing `o`.
void add_query_options(CLI::App& app, QueryOptions& o);
/// Runs and prints the query microbenchmark; 0, or 1 if the methods' hits disagree.
int query_command(const QueryOptions& o);
/// parse_command("query", add_query_options, args), then query_command; 0 after --help.
int query_command(const std::vector<std::string>& args);

}  // namespace hail::bench
