// hail-bench: the benchmark tool. Every time it prints comes with the run's error figures,
// the machine, the SIMD path and a hash of the final state. The command line and the commands
// are bench/command_line.cpp and bench/*_command.cpp, in hail_bench_lib, where the tests reach them.

#include <string>
#include <vector>

#include "command_line.h"

int main(int argc, char** argv) { return hail::bench::hail_bench(std::vector<std::string>(argv + 1, argv + argc)); }
