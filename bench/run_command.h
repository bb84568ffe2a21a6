#pragma once
// `hail-bench run <scene>`: builds a scene, steps it, prints time next to its error figures.

#include <string>
#include <vector>

namespace hail::bench {

int run_command(const std::vector<std::string>& args);

}  // namespace hail::bench
