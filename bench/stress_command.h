#pragma once
// `hail-bench stress`: runs the stability battery (bench/stress_cases.h) and prints each case,
// its invariants and the worst values measured; exit status 1 when any case fails.

#include <string>
#include <vector>

namespace hail::bench {

int stress_command(const std::vector<std::string>& args);

}  // namespace hail::bench
