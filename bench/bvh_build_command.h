#pragma once
// `hail-bench bvh-build`: BVH build times (median split and binned SAH) by heightmap size, over
// terrain-rain's height function.

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench bvh-build`.
struct BvhBuildCommandOptions {
  int max_side = 1024;
};

/// Declares bvh-build's flags on `app`, writing `o`.
void add_bvh_build_options(CLI::App& app, BvhBuildCommandOptions& o);
/// Builds and times the BVHs, prints the table; 0.
int bvh_build_command(const BvhBuildCommandOptions& o);
/// parse_command("bvh-build", add_bvh_build_options, args), then bvh_build_command; 0 after --help.
int bvh_build_command(const std::vector<std::string>& args);

}  // namespace hail::bench
