#pragma once
// One measured run of a scene: build it, step it, time every step, then measure its error
// figures. `hail-bench run` prints one; `hail-bench scale` collects many.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "scenes/metrics.h"
#include "scenes/scenes.h"

namespace hail::bench {

struct RunResult {
  std::string scene, description;
  std::size_t spheres = 0;
  int threads = 0, steps = 0, warmup = 0, reorder_interval = 0;
  float warm_start_factor = 1.0f;
  float dt = 0;
  double mean_ms = 0, median_ms = 0, total_s = 0, setup_s = 0;
  PhaseTimes phase_ms;  ///< mean per timed step
  double static_contacts = 0, sphere_contacts = 0, warm_started = 0, colours = 0, collision_passes = 0,
         depenetration_passes = 0;                ///< mean per timed step
  double tile_contacts = 0, shared_contacts = 0;  ///< mean per timed step: solved within a solver tile / across tiles
  double parallel_loops = 0, crew_stages = 0;     ///< mean per timed step: fork-joins and solver barriers (StepStats)
  ErrorFigures errors;
  double energy_start = 0, energy_drift = 0, momentum_drift = 0;
  std::string state_hash;
  std::string pair_search;  ///< the search the last step used
  bool continuous_collision = true;
  std::string solver;  ///< "passes", or "soft (S substeps, C cycles, damping D, R relax)"
  /// Checked after every step (untimed), for every scene with a terrain or planes
  /// (tunnelling_checked): fast spheres that tunnel soon leave the terrain's extent, and light
  /// ones driven through may be pushed back out, where the end count (errors.tunnelled) no
  /// longer sees them.
  TunnellingFigures tunnelling;
  bool tunnelling_checked = false;  ///< the world has a terrain or planes to tunnel through
  /// J, the largest kinetic energy of the run (the start included) and the step after which it
  /// was reached (0: the start): a run that gains energy shows it here even when it ends calm.
  double energy_peak = 0;
  int energy_peak_step = 0;
  double swept = 0, sweep_events = 0;  ///< continuous collision: spheres swept and impacts, mean per timed step
  double swept_meeting_spheres = 0;    ///< of the swept, those swept against spheres too (mean per timed step)
  std::size_t sweep_capped = 0;        ///< spheres that reached max_sweep_events, summed over all steps
  std::size_t sweep_held = 0;          ///< impacts in which the ground held a light sphere, summed over all steps
  /// Sleeping (WorldSettings::sleep): whether it was on; spheres asleep and awake spheres ready
  /// to sleep, mean per timed step and after the last step (StepStats::sleeping, ready_to_sleep).
  bool sleep = false;
  double sleeping = 0, ready_to_sleep = 0;
  std::size_t sleeping_at_end = 0, ready_to_sleep_at_end = 0;
  /// Memory (scenes/memory_use.h), measured outside the timed steps: the heap the run added,
  /// after set-up (the World with its spheres, the terrain) and at the end (everything the
  /// World keeps between steps too: contacts, solver arrays, caches); 0 where the C library
  /// cannot say. terrain_bytes is Terrain::memory_bytes(), 0 without a terrain.
  std::size_t heap_after_setup = 0, heap_at_end = 0, terrain_bytes = 0;
  bool heap_measured = false;
  /// World::memory_use() at the end: where the World's bytes go, by part (capacities; measured
  /// everywhere, sanitizers included).
  MemoryUse memory_parts;
  /// (heap_at_end - terrain_bytes) / spheres: what each sphere costs, its share of the World's
  /// per-step arrays included.
  [[nodiscard]] double bytes_per_sphere() const {
    return spheres == 0 || heap_at_end < terrain_bytes ? 0.0 : double(heap_at_end - terrain_bytes) / double(spheres);
  }
  /// Substeps in which each optional part of the step ran (StepStats::ran), over all steps.
  struct PartCounts {
    int reorder = 0, detect_static = 0, detect_pairs = 0, solve = 0, friction = 0, rotation = 0, shock = 0, sweep = 0,
        depenetrate = 0, terrain_guard = 0;
  } parts_ran;
};

/// "detect-pairs 600/600, solve 600/600, ..." and "skipped: ..." for the parts of RunResult::parts_ran.
std::string describe_parts(const RunResult& r);

struct RunOptions {
  int steps = -1;               ///< -1: the scene's default
  std::string trace_path;       ///< non-empty: write a Chrome trace there
  bool progress = true;         ///< a line on stderr every 2 s
  std::string progress_label;   ///< prefix of the progress lines
  std::string dump_state_path;  ///< non-empty: write every sphere's final state there (write_state_csv)
  /// > 0 (with dump_state_path): also the state before the first step and after every
  /// dump_every-th, each to step_dump_path(dump_state_path, step); untimed.
  int dump_every = 0;
  /// Called after every step (untimed) with the scene and the step's number from 1, e.g. to
  /// shift the origin mid-run (`hail-bench run --origin D --home-after K`).
  std::function<void(Scene&, int)> after_step;
};

/// Where --dump-every writes the state after `step` steps: `path` with "-" and the step, zero-padded
/// to 6 digits, inserted before its extension ("out/state.csv", 60: "out/state-000060.csv"; a
/// path without an extension gets it appended).
std::string step_dump_path(const std::string& path, int step);

/// The registered scene of that name; InvalidArgument-style std::invalid_argument listing the known ones.
const SceneEntry& find_scene(const std::string& name);

/// Builds and runs the scene; times steps warmup..steps-1 (warmup = 60 when steps > 120, the
/// scenes' definition, else 0).
RunResult run_scene(const SceneEntry& entry, const SceneParams& params, const RunOptions& options);

/// The same for a scene made by `build` (a scene file): `name` is what the result calls it;
/// building counts as set-up time; steps of the scene's own dt.
RunResult run_scene(const std::string& name, const std::function<Scene()>& build, const RunOptions& options);

/// CSV of every sphere's state, `id,x,y,z,vx,vy,vz,wx,wy,wz`, one row per sphere in the order
/// the scene added them (id = that index), floats as %.9g so they read back bit for bit.
void write_state_csv(const Scene& scene, const std::string& path);

/// Every figure of the run, as `hail-bench run --json` writes it.
nlohmann::json to_json(const RunResult& r);

/// 16 hex digits.
std::string hex_hash(std::uint64_t h);

}  // namespace hail::bench
