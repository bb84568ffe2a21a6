#include "gnuplot.h"

#include <cstdio>

#include "run_program.h"

namespace hail::bench {

std::string gnuplot_string(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text)
    if (c != '\'') quoted += c;
  return quoted + "'";
}

bool plot_with_gnuplot(const std::string& dir, const std::string& script, const std::string& assignments,
                       const std::string& made, const std::string& program) {
  std::fflush(stdout);  // the program writes to the same stdout
  const ProgramOutcome run = run_program({program, "-e", assignments, script}, dir);
  if (run.succeeded()) {
    std::printf("  plots: %s\n", made.c_str());
    return true;
  }
  const std::string by_hand =
      "cd " + shell_quoted(dir) + " && " + program + " -e " + shell_quoted(assignments) + " " + script;
  if (!run.started)
    std::printf(
        "  plots: %s (gnuplot not installed? sudo apt-get install gnuplot-nox); the data and %s are in %s/: %s\n",
        run.error.c_str(), script.c_str(), dir.c_str(), by_hand.c_str());
  else
    std::printf("  plots: %s failed (exit status %d); run it by hand: %s\n", program.c_str(), run.exit_status,
                by_hand.c_str());
  return false;
}

}  // namespace hail::bench
