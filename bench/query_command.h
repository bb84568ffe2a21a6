#pragma once
// `hail-bench query`: terrain query microbenchmark (stackless BVH walk, stack walk, brute force,
// direct grid-cell lookup) and `hail-bench bvh-build`: BVH build times by heightmap size.

#include <string>
#include <vector>

namespace hail::bench {

int query_command(const std::vector<std::string>& args);
int bvh_build_command(const std::vector<std::string>& args);

}  // namespace hail::bench
