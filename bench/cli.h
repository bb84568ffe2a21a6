#pragma once
// What every hail-bench command shares on its command line, on CLI11 (Debian's libcli11-dev): a
// count is a whole number in its range ("1e6" is one, "2.7" and "1e10" are refused), a real is a
// finite number in its range, an unknown flag is an error naming it, `--help` prints the
// command's own usage, and the last of a repeated flag wins. Each command declares its flags
// beside its code, in add_<command>_options(CLI::App&, Options&) in bench/<command>_command.cpp;
// command_line.cpp makes those apps the subcommands of `hail-bench`, and parse_command() parses
// one command alone (the tests, an embedding program).
// CLI11 2.1 is header only, and its header alone costs about 10 s of CPU per file that includes
// it in Release (GCC 12, -O2) and 44 s under ASan + UBSan: hail_bench_lib parses it once, into a
// precompiled header (bench/CMakeLists.txt), and no other header includes it (they declare
// CLI::App forward). Values inside a list are read with parse_numbers.h, which needs
// no CLI11.

#include <CLI/CLI.hpp>
#include <concepts>
#include <optional>
#include <string>
#include <vector>

#include "parse_numbers.h"

namespace hail::bench {

/// A CLI11 transform: the text as a whole number in [min, max], rewritten as plain digits for
/// the conversion that follows; otherwise "must be a whole number in [1, 100000000], got '2.7'"
/// (CLI11 puts the flag in front: "--steps: must be ...").
[[nodiscard]] CLI::Validator whole_number_in(long long min, long long max);
/// A CLI11 check: a finite number in [min, max] ((min, max] with exclude_min).
[[nodiscard]] CLI::Validator number_in(double min, double max, bool exclude_min = false);

/// A whole-number flag (whole_number_in) writing `target`; its default is shown in --help.
template <std::integral T>
CLI::Option* add_count(CLI::App& app, const std::string& name, T& target, long long min, long long max,
                       const std::string& help) {
  return app.add_option(name, target, help)->transform(whole_number_in(min, max))->type_name("N");
}
/// A real-number flag (number_in) writing `target`.
template <std::floating_point T>
CLI::Option* add_number(CLI::App& app, const std::string& name, T& target, double min, double max,
                        const std::string& help, bool exclude_min = false) {
  return app.add_option(name, target, help)->check(number_in(min, max, exclude_min))->type_name("X");
}

/// The conventions every command's app follows (the last of a repeated flag wins); call before
/// adding its options.
void use_bench_conventions(CLI::App& app);

/// Parses `args` (the words after the command's name) with `app`: false after --help (the usage
/// printed on stdout); any other CLI11 error as std::invalid_argument with CLI11's message
/// (which names the flag) and "(see hail-bench COMMAND --help)".
[[nodiscard]] bool parse_command_line(CLI::App& app, const std::vector<std::string>& args);

/// One command parsed alone: its options as add_options declares them, or nothing after --help.
template <class Options>
std::optional<Options> parse_command(const std::string& name, void (*add_options)(CLI::App&, Options&),
                                     const std::vector<std::string>& args) {
  Options options;
  CLI::App app("", "hail-bench " + name);
  use_bench_conventions(app);
  add_options(app, options);
  if (!parse_command_line(app, args)) return std::nullopt;
  return options;
}

}  // namespace hail::bench
