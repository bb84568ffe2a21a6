#pragma once
// `hail-bench query`: terrain query microbenchmark (stackless BVH walk, stack walk, brute force,
// direct grid-cell lookup) and `hail-bench bvh-build`: BVH build times by heightmap size.

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

/// Every flag of `hail-bench bvh-build`.
struct BvhBuildCommandOptions {
  int max_side = 1024;
};

/// Declares query's flags on `app`, writing `o`.
void add_query_options(CLI::App& app, QueryOptions& o);
/// Runs and prints the query microbenchmark; 0, or 1 if the methods' hits disagree.
int query_command(const QueryOptions& o);
/// parse_command("query", add_query_options, args), then query_command; 0 after --help.
int query_command(const std::vector<std::string>& args);

/// Declares bvh-build's flags on `app`, writing `o`.
void add_bvh_build_options(CLI::App& app, BvhBuildCommandOptions& o);
/// Builds and times the BVHs, prints the table; 0.
int bvh_build_command(const BvhBuildCommandOptions& o);
/// parse_command("bvh-build", add_bvh_build_options, args), then bvh_build_command; 0 after --help.
int bvh_build_command(const std::vector<std::string>& args);

}  // namespace hail::bench
