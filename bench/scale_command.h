#pragma once
// `hail-bench scale <scene>`: the scene at doubling sphere counts and every thread count from
// 1 to the hardware's; table on stdout, CSV and JSON in a folder, plots through gnuplot.

#include <string>
#include <vector>

namespace hail::bench {

int scale_command(const std::vector<std::string>& args);

}  // namespace hail::bench
