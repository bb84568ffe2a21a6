#pragma once
// The plot step shared by `hail-bench accuracy` and `scale`: gnuplot run on a script written
// beside the data, in the output folder, started without a shell (run_program.h).

#include <string>

namespace hail::bench {

/// `text` as a gnuplot string constant, '...', with any ' left out (it would end the string
/// and let the rest run as gnuplot commands, which include system()).
[[nodiscard]] std::string gnuplot_string(const std::string& text);

/// Runs `program` (gnuplot) in `dir` as `program -e ASSIGNMENTS SCRIPT` (SCRIPT a file in
/// `dir`) and prints one "  plots: " line: `made` when it succeeded, else why not and the
/// command to run by hand. True if it succeeded.
bool plot_with_gnuplot(const std::string& dir, const std::string& script, const std::string& assignments,
                       const std::string& made, const std::string& program = "gnuplot");

}  // namespace hail::bench
