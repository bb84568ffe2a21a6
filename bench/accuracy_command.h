#pragma once
// `hail-bench accuracy`: error against wall time. The known-answer cases (accuracy_cases.h) for
// every engine and cost knob at several dt, and terrain-rain / bowl-pile against a reference
// run at dt / 16; a table, CSV and JSON, and work-precision plots through gnuplot.

#include <string>
#include <vector>

namespace hail::bench {

int accuracy_command(const std::vector<std::string>& args);

}  // namespace hail::bench
