#pragma once
// `hail-bench accuracy`: error against wall time. The known-answer cases (accuracy_cases.h) for
// every engine and cost knob at several dt, and terrain-rain / bowl-pile against a reference
// run at dt / 16; a table, CSV and JSON, and work-precision plots through gnuplot.

#include <cstddef>
#include <string>
#include <vector>

#include "hail/world_settings.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench accuracy`.
struct AccuracyOptions {
  std::vector<double> dts{1.0 / 60.0, 1.0 / 240.0, 1.0 / 1000.0};
  std::size_t scene_spheres = 1000;
  int repeats = 3;
  std::string out_dir = "hail-out/accuracy";
  bool no_plot = false, no_scenes = false, quiet = false;
  /// settings.soft_step: the soft step's knobs of the hail-soft variant (--substeps,
  /// --contact-cycles, ...); the hail-soft-N-substeps variants differ from it in the substeps alone.
  WorldSettings settings{};
  /// --variants: only these engines / knobs (names as the table prints them); empty: all.
  std::vector<std::string> only;
};

/// Declares accuracy's flags on `app`, writing `o`.
void add_accuracy_options(CLI::App& app, AccuracyOptions& o);
/// Runs every case, prints the table, writes the files; the process exit status.
int accuracy_command(const AccuracyOptions& o);
/// parse_command("accuracy", add_accuracy_options, args), then accuracy_command; 0 after --help.
int accuracy_command(const std::vector<std::string>& args);

}  // namespace hail::bench
