#pragma once
// The whole hail-bench command line: every command is a CLI11 subcommand whose flags its own
// add_<command>_options declares; `--simd PATH` belongs to hail-bench itself and may come
// before or after the command. main.cpp is this and nothing more, so the tests run it too.

#include <string>
#include <vector>

namespace hail::bench {

/// Parses `args` (argv without the program name), runs the command and returns the process exit
/// status: 0 (also after --help), 2 for a bad command line (the message on stderr names the
/// flag), 1 if a run or a write failed, 3 if a run ended with NaN (stress: 1 if a case failed).
int hail_bench(const std::vector<std::string>& args);

}  // namespace hail::bench
