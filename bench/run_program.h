#pragma once
// Starts another program (gnuplot, for the plots of accuracy and scale) with an argument
// vector and no shell between: a folder name or value containing quotes, `;` or `$(...)`
// reaches the program as the text it is and is never run as a command.

#include <string>
#include <vector>

namespace hail::bench {

struct ProgramOutcome {
  bool started = false;  ///< false: not found in PATH (or could not be started); see `error`
  int exit_status = -1;  ///< the program's exit status; -1 if it did not exit normally (a signal)
  std::string error;     ///< why it did not start
  [[nodiscard]] bool succeeded() const { return started && exit_status == 0; }
};

/// Runs `argv[0]` (looked up in PATH, as execvp does) with `argv` as its arguments, in the
/// folder `working_dir`, and waits for it. The caller's standard streams are the program's.
[[nodiscard]] ProgramOutcome run_program(const std::vector<std::string>& argv, const std::string& working_dir);

/// `text` quoted for a POSIX shell ('...', each ' as '\''): for printing a command line the
/// user may paste, never for running one.
[[nodiscard]] std::string shell_quoted(const std::string& text);

}  // namespace hail::bench
