#pragma once
// `hail-bench compare <scene>`: hail and Bullet on the identical scene in one process run,
// repetitions alternating, one table of ms/step and error figures side by side.

#include <string>
#include <vector>

#include "scenes/scene_run.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench compare`.
struct CompareOptions {
  std::string scene = "terrain-rain";
  SceneParams params;
  int steps = -1;  // -1: the scene's default
  int repeat = 3;
  std::string json_path;
  bool quiet = false;
};

/// Declares compare's flags on `app`, writing `o`.
void add_compare_options(CLI::App& app, CompareOptions& o);
/// Runs both engines and prints the table; the process exit status.
int compare_command(const CompareOptions& o);
/// parse_command("compare", add_compare_options, args), then compare_command; 0 after --help.
int compare_command(const std::vector<std::string>& args);

}  // namespace hail::bench
