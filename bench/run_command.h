#pragma once
// `hail-bench run <scene>`: builds a scene, steps it, prints time next to its error figures.

#include <string>
#include <vector>

#include "scenes/scene_run.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Every flag of `hail-bench run`.
struct RunCommandOptions {
  std::string scene = "implosion";
  SceneParams params;
  int steps = -1;  // -1: the scene's default
  std::string json_path;
  std::string trace_path;
  bool quiet = false;
  std::string scene_file;       // --scene FILE.json (instead of a scene name)
  std::string dump_state_path;  // --dump-state FILE.csv
  int dump_every = 0;           // --dump-every K (0: the final state only)
  bool scene_named = false;
  std::vector<std::string> given;  // --spheres, --threads, --steps, --dt if given: a scene file yields to these
  std::vector<std::string> given_settings;  // the setting flags given, as NAME=VALUE (bench/setting_flags.h)
  bool ccd_both = false;                    // --ccd-both: alternate runs with continuous collision on and off
  int repeat = 0;                           // --repeat N (0: 1, or 3 with --ccd-both)
  double memory_limit_gb = -1.0;   // --memory-limit GB (< 0: 80% of the memory available; 0: none)
  double origin = 0.0;             // --origin D: the scene moved by (D, 0, D) m (scenes/scene_origin.cpp)
  int home_after = 0;              // --home-after K: after step K, shift the scene back by (D, 0, D)
  std::string filters = "none";    // --filters none|accept-all|teams|compare (scenes/scene_filters.h)
  int save_at = 0;                 // --save-at STEP FILE: World::save_file after step STEP (0: none)
  std::string save_path;
  std::string restore_path;        // --restore FILE: World::restore_file once the scene is built
  std::string expect_hash;         // --expect-hash H: exit status 1 unless the final state hash is H
  std::string record_path;         // --record FILE: positions every --every K steps (hail/recording.h)
  int record_every = 1;            // --every K
  bool record_velocities = false;  // --velocities: frames carry velocities too
  std::string vtk_dir;             // --vtk DIR: ParaView frames at step 0 and every --vtk-every K steps
  int vtk_every = 1;
};

/// Declares run's flags on `app`, writing `o`; the checks between flags run once `app` is parsed.
void add_run_options(CLI::App& app, RunCommandOptions& o);

/// What `hail-bench run --quiet` prints, one line: "NAME: N spheres, S steps, T ms/step, worst
/// penetration P m, tunnelled K (E sphere-steps), NaN 0, hash H" (the worst penetration of any
/// timed step, spheres or ground; "tunnelled -" for a world with no terrain or planes).
std::string summary_line(const RunResult& r);

/// Every run `hail-bench run` made, in order.
struct RunCommandResult {
  std::vector<RunResult> runs;                     ///< --repeat R runs (one by default)
  std::vector<RunResult> ccd_on, ccd_off;          ///< --ccd-both: the runs with continuous collision on, and off
  std::vector<std::vector<RunResult>> by_filters;  ///< --filters compare: the runs of each scene_filter_names() entry
};

/// Checks the outputs and the memory limit before anything is built, then run_runs and
/// report_runs; the process exit status (3 if a run ended with NaN, 1 if --expect-hash differs).
int run_command(const RunCommandOptions& o);
/// Builds and steps the scene as often as `o` asks (progress on stderr unless --quiet).
RunCommandResult run_runs(const RunCommandOptions& o);
/// Prints the report (or with --quiet the summary line, with --ccd-both the table) and writes
/// --json; the process exit status (3 if a run ended with NaN).
int report_runs(const RunCommandOptions& o, const RunCommandResult& result);
/// parse_command("run", add_run_options, args), then run_command; 0 after --help.
int run_command(const std::vector<std::string>& args);

}  // namespace hail::bench
