#include "run_command.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "cli.h"
#include "hail/recording.h"
#include "scenes/machine_info.h"
#include "scenes/memory_use.h"
#include "scenes/output_file.h"
#include "scenes/scene_file.h"
#include "scenes/scene_filters.h"
#include "scenes/scene_inputs.h"
#include "scenes/scene_run.h"
#include "scenes/setting_text.h"
#include "scenes/vtk_frames.h"
#include "setting_flags.h"

namespace hail::bench {
namespace {

[[noreturn]] void usage_error(const std::string& message) { throw std::invalid_argument(message); }

using CommandOptions = RunCommandOptions;

/// The flags given on the command line, which override a scene file's values.
SceneOverrides file_overrides(const CommandOptions& o) {
  auto given = [&](const char* flag) { return std::find(o.given.begin(), o.given.end(), flag) != o.given.end(); };
  SceneOverrides v;
  v.memory_limit = memory_limit(o.memory_limit_gb);  // the file's own counts and terrain are checked against it
  if (given("--spheres")) v.spheres = o.params.spheres;
  if (given("--threads")) v.threads = o.params.threads;
  if (given("--steps")) v.steps = o.steps;
  if (given("--dt")) v.dt = o.params.dt;
  // The setting flags given, then the --set ones: the scene file reads them as it reads --set.
  v.set = o.given_settings;
  v.set.insert(v.set.end(), o.params.set.begin(), o.params.set.end());
  return v;
}

/// What --save-at and --restore took, for the report: the snapshot's bytes, and ms to save or
/// restore it (file I/O included).
struct SnapshotFigures {
  std::size_t bytes = 0;
  double save_ms = 0.0, restore_ms = 0.0;
};
SnapshotFigures snapshot_figures;

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// The scene's world made the snapshot's (--restore), its handles (for --dump-state) the
/// restored world's, by index (the order a scene adds them in).
void restore_scene(Scene& scene, const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  scene.world->restore_file(path);
  snapshot_figures.restore_ms = ms_since(start);
  snapshot_figures.bytes = std::filesystem::file_size(path);
  const std::span<const SphereId> handles = scene.world->handles();
  scene.ids.assign(handles.begin(), handles.end());
  std::sort(scene.ids.begin(), scene.ids.end(), [](SphereId a, SphereId b) { return a.index < b.index; });
}

/// --record: the file and its writer, frame 0 written once the scene is built, a frame after
/// every --every K steps (untimed), the end marker once the run is over.
/// The file is written beside its target and renamed over it once finished (AtomicOutputFile),
/// so a run that fails or a disk that fills leaves the old recording whole.
struct Recorder {
  std::optional<AtomicOutputFile> file;
  std::optional<RecordingWriter> writer;
  RecordingFrame frame;  // reused

  void begin(const CommandOptions& o, const std::string& name, const Scene& scene) {
    writer.reset();
    file.reset();
    file.emplace(o.record_path);
    writer.emplace(file->stream(), recording_header(*scene.world, scene.ids, name, scene.dt,
                                                    static_cast<std::uint32_t>(o.record_every), o.record_velocities));
    write(scene, 0);
  }
  void write(const Scene& scene, int step) {
    recording_frame(*scene.world, writer->header(), static_cast<std::uint64_t>(step), frame);
    writer->write_frame(frame);
  }
};

/// One run of the scene (named or from a file) with these parameters.
RunResult run_once(const CommandOptions& o, const SceneParams& params, bool last, const std::string& filters) {
  RunOptions run_options{.steps = o.steps,
                         .trace_path = last ? o.trace_path : "",
                         .progress = !o.quiet,
                         .progress_label = "",
                         .dump_state_path = last ? o.dump_state_path : "",
                         .dump_every = last ? o.dump_every : 0,
                         .after_step = {}};
  const float d = static_cast<float>(o.origin);
  const bool save = last && o.save_at > 0;
  const bool record = last && !o.record_path.empty();
  Recorder recorder;
  // --vtk: ParaView frames (scenes/vtk_frames.h) of the last run, untimed, as --record's.
  std::optional<VtkFrames> vtk;
  if (last && !o.vtk_dir.empty()) vtk.emplace(o.vtk_dir);
  if (o.home_after > 0 || save || record || vtk)
    run_options.after_step = [&](Scene& scene, int step) {
      if (step == o.home_after) move_scene(scene, Vec3(-d, 0.0f, -d));
      if (record && step % o.record_every == 0) recorder.write(scene, step);
      if (vtk && step % o.vtk_every == 0) vtk->write(*scene.world, double(step) * double(scene.dt));
      if (save && step == o.save_at) {
        const auto start = std::chrono::steady_clock::now();
        scene.world->save_file(o.save_path);
        snapshot_figures.save_ms = ms_since(start);
        snapshot_figures.bytes = std::filesystem::file_size(o.save_path);
      }
    };
  const SceneFilters filter_mode = scene_filters_named(filters);
  auto moved = [&](Scene scene) {
    if (d != 0.0f) move_scene(scene, Vec3(d, 0.0f, d));
    give_filters(scene, filter_mode);
    if (!o.restore_path.empty()) restore_scene(scene, o.restore_path);
    if (record) recorder.begin(o, o.scene_file.empty() ? o.scene : o.scene_file, scene);
    if (vtk) vtk->write(*scene.world, 0.0);
    return scene;
  };
  RunResult result;
  if (o.scene_file.empty()) {
    const SceneEntry& entry = find_scene(o.scene);
    result = run_scene(
        entry.name, [&] { return moved(entry.build(params)); }, run_options);
  } else {
    CommandOptions file_options = o;
    file_options.params = params;
    result = run_scene(
        o.scene_file, [&] { return moved(load_scene_file(o.scene_file, file_overrides(file_options))); }, run_options);
  }
  if (record) {
    recorder.writer->finish();
    recorder.file->commit();
  }
  return result;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void print_report(const RunResult& r) {
  const ErrorFigures& e = r.errors;
  const PhaseTimes& p = r.phase_ms;
  std::printf("hail-bench run %s  (%s)\n", r.scene.c_str(), r.description.c_str());
  std::printf("  machine   %s, %d threads, SIMD %s\n", cpu_model().c_str(), r.threads, simd_description().c_str());
  std::printf(
      "  scene     %zu spheres, %d steps of dt = %.6g s, Morton re-sort every %d steps, continuous collision %s\n",
      r.spheres, r.steps, r.dt, r.reorder_interval, r.continuous_collision ? "on" : "off");
  std::printf("  time      %.3f ms/step mean, %.3f median (steps %d..%d), total %.3f s, set-up %.3f s\n", r.mean_ms,
              r.median_ms, r.warmup, r.steps - 1, r.total_s, r.setup_s);
  std::printf(
      "  phases    reorder %.3f  predict %.3f  detect-terrain %.3f  detect-pairs %.3f  solve %.3f  sweep %.3f  "
      "integrate %.3f  depenetrate %.3f ms\n",
      p.reorder, p.predict, p.detect_terrain, p.detect_pairs, p.solve, p.sweep, p.integrate, p.depenetrate);
  std::printf("  parts     %s\n", describe_parts(r).c_str());
  if (r.sleep)
    std::printf(
        "  sleep     per step: %.0f spheres asleep, %.0f awake and ready to sleep, islands phase %.3f ms; after the "
        "last step: %zu asleep, %zu ready\n",
        r.sleeping, r.ready_to_sleep, p.islands, r.sleeping_at_end, r.ready_to_sleep_at_end);
  std::printf("  solver    %s\n", r.solver.c_str());
  std::printf(
      "  contacts  pairs by %s; per step: %.0f static + %.0f sphere contacts (%.0f warm-started), %.1f colours, %.2f "
      "collision passes that applied an impulse, %.2f depenetration passes\n",
      r.pair_search.c_str(), r.static_contacts, r.sphere_contacts, r.warm_started, r.colours, r.collision_passes,
      r.depenetration_passes);
  std::printf("  tiles     per step: %.0f contacts solved within a solver tile, %.0f across tiles (--tile)\n",
              r.tile_contacts, r.shared_contacts);
  std::printf("  sync      per step: %.1f parallel loops (a fork and a join each), %.1f solver stages (a barrier each)\n",
              r.parallel_loops, r.crew_stages);
  if (r.continuous_collision)
    std::printf(
        "  sweep     per step: %.1f spheres swept (%.1f against spheres too), %.1f impacts at their time; "
        "%zu times a sphere reached the impact cap, %zu struck spheres held by the ground or a heavier sphere\n",
        r.swept, r.swept_meeting_spheres, r.sweep_events, r.sweep_capped, r.sweep_held);
  std::printf("  error     max penetration %.4g m (spheres) %.4g m (ground), tunnelled %zu, fell off %zu, NaN %zu\n",
              e.max_sphere_penetration, e.max_terrain_penetration, e.tunnelled, e.fell_off, e.nan_count);
  std::printf(
      "  worst     penetration any timed step started from: %.4g m (spheres) %.4g m (ground and planes); "
      "a step's deepest, mean: %.4g / %.4g m\n",
      e.worst_sphere_penetration, e.worst_static_penetration, e.mean_step_sphere_penetration,
      e.mean_step_static_penetration);
  if (r.tunnelling_checked)
    std::printf(
        "  tunnel    %zu spheres tunnelled, %zu sphere-steps with the centre below the terrain or behind a plane, "
        "deepest %.4g m (checked after every step)\n",
        r.tunnelling.spheres, r.tunnelling.events, r.tunnelling.worst_depth);
  std::printf(
      "  energy    kinetic %.6g J (start %.6g J, drift %+.3e; peak %.6g J after step %d), momentum drift %.3e kg m/s\n",
      e.kinetic_energy, r.energy_start, r.energy_drift, r.energy_peak, r.energy_peak_step, r.momentum_drift);
  if (r.heap_measured)
    std::printf("  memory    heap %s after set-up, %s at the end (terrain %s; %.0f bytes per sphere besides)\n",
                format_bytes(double(r.heap_after_setup)).c_str(), format_bytes(double(r.heap_at_end)).c_str(),
                format_bytes(double(r.terrain_bytes)).c_str(), r.bytes_per_sphere());
  {
    // World::memory_use: bytes per sphere by part, what the heap line's "besides" is made of.
    const MemoryUse& m = r.memory_parts;
    const double n = r.spheres > 0 ? double(r.spheres) : 1.0;
    std::printf("  bytes     per sphere by part:");
    const char* separator = " ";
    m.for_each_part([&](const char* name, std::size_t bytes) {
      std::printf("%s%s %.0f", separator, name, double(bytes) / n);
      separator = ", ";
    });
    std::printf("; %.0f in all\n", double(m.total()) / n);
  }
  std::printf("  state     hash %s\n", r.state_hash.c_str());
}

}  // namespace

std::string summary_line(const RunResult& r) {
  const ErrorFigures& e = r.errors;
  char line[512];
  std::snprintf(line, sizeof line, "%s: %zu spheres, %d steps, %.3f ms/step, worst penetration %.4g m, ",
                r.scene.c_str(), r.spheres, r.steps, r.mean_ms,
                std::max(e.worst_sphere_penetration, e.worst_static_penetration));
  std::string text = line;
  if (r.tunnelling_checked)
    std::snprintf(line, sizeof line, "tunnelled %zu (%zu sphere-steps), ", r.tunnelling.spheres, r.tunnelling.events);
  else
    std::snprintf(line, sizeof line, "tunnelled -, ");
  text += line;
  std::snprintf(line, sizeof line, "NaN %zu, hash %s", e.nan_count, r.state_hash.c_str());
  return text + line;
}

namespace {

/// --ccd-both: runs with continuous collision on and off, alternating in ABBA order so that a
/// drift in machine speed falls on both alike.
void run_both(const CommandOptions& o, RunCommandResult& result) {
  const int repeat = o.repeat > 0 ? o.repeat : 3;
  for (int k = 0; k < 2 * repeat; ++k) {
    const bool ccd = (k % 4 == 0 || k % 4 == 3);
    SceneParams params = o.params;
    params.set.push_back(ccd ? "continuous_collision=on" : "continuous_collision=off");  // last: a scene file's too
    if (!o.quiet) std::fprintf(stderr, "  run %d/%d: continuous collision %s\n", k + 1, 2 * repeat, ccd ? "on" : "off");
    (ccd ? result.ccd_on : result.ccd_off).push_back(run_once(o, params, k + 2 >= 2 * repeat, o.filters));
  }
}

/// --ccd-both's table, with the ratio of the medians, and its JSON.
int report_both(const CommandOptions& o, const RunCommandResult& result) {
  const std::vector<RunResult>& on = result.ccd_on;
  const std::vector<RunResult>& off = result.ccd_off;
  const int repeat = static_cast<int>(on.size());
  auto medians = [](const std::vector<RunResult>& runs) {
    std::vector<double> m;
    for (const RunResult& r : runs) m.push_back(r.median_ms);
    return m;
  };
  const RunResult& a = on.back();
  const RunResult& b = off.back();
  std::printf("hail-bench run %s --ccd-both  (%s)\n", a.scene.c_str(), a.description.c_str());
  std::printf("  machine   %s, %d threads, SIMD %s; %zu spheres, %d steps of dt = %.6g s; %d runs each, ABBA order\n",
              cpu_model().c_str(), a.threads, simd_description().c_str(), a.spheres, a.steps, a.dt, repeat);
  std::printf("  %-4s %10s %10s %9s %9s %10s %10s %9s %9s %9s %5s  %s\n", "ccd", "ms/step", "(runs)", "swept",
              "impacts", "pen. sph", "pen. gnd", "tunnelled", "ever", "fell off", "NaN", "hash");
  for (const auto* runs : {&on, &off}) {
    const RunResult& r = runs->back();
    const std::vector<double> m = medians(*runs);
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a known false positive) about
    // "literal" + std::string temporaries here.
    std::string spread = "(";
    for (double x : m) {
      if (spread.size() > 1) spread += ' ';
      spread += std::to_string(x).substr(0, 5);
    }
    spread += ')';
    std::printf("  %-4s %10.3f %10s %9.1f %9.1f %10.4g %10.4g %9zu %9s %9zu %5zu  %s\n", runs == &on ? "on" : "off",
                median_of(m), spread.c_str(), r.swept, r.sweep_events, r.errors.max_sphere_penetration,
                r.errors.max_terrain_penetration, r.errors.tunnelled,
                r.tunnelling_checked ? std::to_string(r.tunnelling.spheres).c_str() : "-", r.errors.fell_off,
                r.errors.nan_count, r.state_hash.c_str());
  }
  std::printf("  ratio on / off of the median ms/step: %.3f\n", median_of(medians(on)) / median_of(medians(off)));
  if (!o.json_path.empty()) {
    nlohmann::json runs = nlohmann::json::array();
    for (const RunResult& r : on) runs.push_back(to_json(r));
    for (const RunResult& r : off) runs.push_back(to_json(r));
    const nlohmann::json out = {{"runs", runs}, {"ratio_on_off", median_of(medians(on)) / median_of(medians(off))}};
    write_file_atomically(o.json_path, [&](std::ostream& file) { file << out.dump(2) << "\n"; });
  }
  return a.errors.nan_count == 0 && b.errors.nan_count == 0 ? 0 : 3;
}

/// --filters compare's table: each mode's median ms/step and its ratio to no filters.
int report_filters(const RunCommandResult& result) {
  const std::vector<std::string>& names = scene_filter_names();
  const RunResult& first = result.by_filters[0].back();
  std::printf("hail-bench run %s --filters compare\n", first.scene.c_str());
  std::printf("  machine   %s, %d threads, SIMD %s; %zu spheres, %d steps; %zu runs each, order turned each round\n",
              cpu_model().c_str(), first.threads, simd_description().c_str(), first.spheres, first.steps,
              result.by_filters[0].size());
  std::vector<double> medians;
  for (const std::vector<RunResult>& runs : result.by_filters) {
    std::vector<double> m;
    for (const RunResult& r : runs) m.push_back(r.median_ms);
    medians.push_back(median_of(m));
  }
  std::printf("  %-11s %10s %8s %10s  %s\n", "filters", "ms/step", "ratio", "contacts", "hash");
  int status = 0;
  for (std::size_t m = 0; m < names.size(); ++m) {
    const RunResult& r = result.by_filters[m].back();
    std::printf("  %-11s %10.3f %8.3f %10.0f  %s\n", names[m].c_str(), medians[m], medians[m] / medians[0],
                r.sphere_contacts, r.state_hash.c_str());
    if (r.errors.nan_count != 0) status = 3;
  }
  return status;
}

}  // namespace

/// Refuses, before anything is built, a sphere count that could not fit the memory limit at
/// kBytesPerSphereGuide a sphere (a scene file's own counts are checked by its reader, through
/// SceneOverrides::memory_limit): the kernel's OOM kill would otherwise end the run after minutes of set-up.
void check_memory(const CommandOptions& o) {
  const bool spheres_known =
      o.scene_file.empty() || std::find(o.given.begin(), o.given.end(), "--spheres") != o.given.end();
  const double limit = memory_limit_bytes(o.memory_limit_gb);
  const double estimate = kBytesPerSphereGuide * double(o.params.spheres);
  if (!spheres_known || limit <= 0.0 || estimate <= limit) return;
  usage_error("--spheres " + std::to_string(o.params.spheres) + " needs about " + format_bytes(estimate) + " (" +
              std::to_string(static_cast<int>(kBytesPerSphereGuide)) +
              " bytes a sphere, the most measured: docs/benchmarks.md, Memory), over the memory limit of " +
              describe_memory_limit(o.memory_limit_gb, limit) + "; --memory-limit GB sets it, 0 turns the check off");
}

int run_command(const RunCommandOptions& o) {
  // Before anything is built: an output that cannot be written, or that would overwrite the
  // scene file (or its heightmap), the --restore snapshot or another output, stops the run now
  // rather than at its end (or at --save-at's step). --dump-every's files lie beside
  // --dump-state's: the first of them stands for them all.
  std::vector<std::string> inputs = scene_file_inputs(o.scene_file);
  inputs.push_back(o.restore_path);
  check_output_paths({o.json_path, o.trace_path, o.dump_state_path, o.record_path, o.save_at > 0 ? o.save_path : "",
                      o.dump_every > 0 ? step_dump_path(o.dump_state_path, 0) : std::string()},
                     inputs);
  check_memory(o);
  const RunCommandResult result = run_runs(o);
  const int status = report_runs(o, result);
  if (o.save_at > 0) {
    const RunResult& r = result.runs.back();
    if (o.save_at > r.steps)
      throw std::invalid_argument("--save-at " + std::to_string(o.save_at) + " is past the run's " +
                                  std::to_string(r.steps) + " steps: no snapshot was written");
    if (!o.quiet)
      std::printf("  snapshot  saved after step %d to %s: %zu bytes in %.2f ms (untimed in the steps)\n", o.save_at,
                  o.save_path.c_str(), snapshot_figures.bytes, snapshot_figures.save_ms);
  }
  if (!o.restore_path.empty() && !o.quiet)
    std::printf("  snapshot  restored from %s: %zu bytes in %.2f ms (in the set-up time)\n", o.restore_path.c_str(),
                snapshot_figures.bytes, snapshot_figures.restore_ms);
  if (!o.expect_hash.empty()) {
    std::string expected = o.expect_hash;
    if (expected.rfind("0x", 0) == 0) expected = expected.substr(2);
    std::transform(expected.begin(), expected.end(), expected.begin(), [](unsigned char c) { return std::tolower(c); });
    const std::string& got = result.runs.back().state_hash;
    if (got != expected) {
      std::fprintf(stderr, "hail-bench run: state hash %s differs from --expect-hash %s\n", got.c_str(),
                   o.expect_hash.c_str());
      return 1;
    }
    if (!o.quiet) std::printf("  check     state hash matches --expect-hash\n");
  }
  return status;
}

RunCommandResult run_runs(const RunCommandOptions& o) {
  RunCommandResult result;
  if (o.ccd_both) {
    run_both(o, result);
    return result;
  }
  const int repeat = o.repeat > 0 ? o.repeat : 1;
  if (o.filters == "compare") {
    // Each round runs every mode, the order turned each round, so that a drift in machine
    // speed falls on all alike.
    const std::vector<std::string>& names = scene_filter_names();
    result.by_filters.resize(names.size());
    const int rounds = o.repeat > 0 ? o.repeat : 3;
    for (int k = 0; k < rounds; ++k)
      for (std::size_t m = 0; m < names.size(); ++m) {
        const std::size_t mode = (m + static_cast<std::size_t>(k)) % names.size();
        if (!o.quiet) std::fprintf(stderr, "  round %d/%d: --filters %s\n", k + 1, rounds, names[mode].c_str());
        result.by_filters[mode].push_back(run_once(o, o.params, false, names[mode]));
      }
    return result;
  }
  for (int k = 0; k < repeat; ++k) result.runs.push_back(run_once(o, o.params, k + 1 == repeat, o.filters));
  return result;
}

int report_runs(const RunCommandOptions& o, const RunCommandResult& result) {
  if (o.ccd_both) return report_both(o, result);
  if (!result.by_filters.empty()) return report_filters(result);
  const std::vector<RunResult>& runs = result.runs;
  const int repeat = static_cast<int>(runs.size());
  const RunResult& r = runs.back();
  if (o.quiet)
    std::printf("%s\n", summary_line(r).c_str());
  else
    print_report(r);
  if (repeat > 1 && !o.quiet) {
    std::vector<double> m;
    std::string all;
    for (const RunResult& x : runs) {
      m.push_back(x.median_ms);
      all += ' ';
      all += std::to_string(x.median_ms).substr(0, 6);
    }
    std::printf("  repeats   median of %d runs' medians: %.3f ms/step (runs:%s)\n", repeat, median_of(m), all.c_str());
  }
  if (!o.dump_state_path.empty() && !o.quiet) {
    std::printf("  dump      final state of every sphere written to %s\n", o.dump_state_path.c_str());
    if (o.dump_every > 0)
      std::printf("  dump      and the state at step 0 and every %d steps to %s, ...\n", o.dump_every,
                  step_dump_path(o.dump_state_path, 0).c_str());
  }
  if (!o.record_path.empty() && !o.quiet)
    std::printf("  record    positions%s at step 0 and every %d steps written to %s (hail-view --replay plays it)\n",
                o.record_velocities ? " and velocities" : "", o.record_every, o.record_path.c_str());
  if (!o.trace_path.empty() && !o.quiet)
    std::printf("  trace     written to %s (open in https://ui.perfetto.dev or chrome://tracing)\n",
                o.trace_path.c_str());
  if (!o.json_path.empty()) {
    write_file_atomically(o.json_path, [&](std::ostream& file) { file << to_json(r).dump(2) << "\n"; });
  }
  return r.errors.nan_count == 0 ? 0 : 3;
}

// The flags of `hail-bench run` (bench/cli.h's rules).

void add_run_options(CLI::App& app, RunCommandOptions& o) {
  SceneParams& p = o.params;
  app.description(
      "step a scene (built-in, or --scene FILE.json); print ms/step, the per-phase split and error figures");
  app.add_option("scene", o.scene, "a built-in scene (hail-bench --help lists them)")
      ->check(CLI::IsMember(scene_names()));
  app.add_option("--scene", o.scene_file, "a scene file (docs/scene_format.md); flags given override its values")
      ->type_name("FILE.json");
  add_count(app, "--spheres", p.spheres, 1, 100'000'000, "sphere count");
  add_count(app, "--steps", o.steps, 1, 100'000'000, "steps (default -1: the scene's)");
  add_count(app, "--threads", p.threads, 0, 4096, "worker threads (0: all)");
  add_number(app, "--dt", p.dt, 0.0, 10.0, "time step, s", /*exclude_min=*/true);
  add_setting_flags(app, p.settings);  // --resting, --solver, ...: the settings table's flags
  app.add_flag("--ccd-both", o.ccd_both, "alternate runs with continuous collision on and off (ABBA), one table");
  app.add_option("--set", p.set,
                 "NAME=VALUE: any setting of the settings table by its name (include/hail/settings_table.h, "
                 "docs/embedding.md#settings), after the setting flags; repeatable, the last of one name wins")
      ->type_name("NAME=VALUE")
      ->check(CLI::Validator(
          [](std::string& v) {
            WorldSettings scratch;
            try {
              set_setting(scratch, v);  // an unknown name, or a value of the wrong kind, stops the parse
            } catch (const std::invalid_argument& e) {
              return std::string(e.what());
            }
            return std::string();
          },
          "NAME=VALUE"));
  add_number(app, "--origin", o.origin, -1e7, 1e7,
             "m; run the scene moved by (D, 0, D) (World::shift_origin), to measure precision far from the origin");
  add_count(app, "--home-after", o.home_after, 1, 100'000'000,
            "with --origin D: after step K, World::shift_origin brings the scene back home (its error stays)");
  app.add_flag("--terrain-as-mesh", o.params.terrain_as_mesh,
               "a heightmap scene's terrain given to World::add_mesh instead (the same triangles through the mesh "
               "path: docs/meshes.md)");
  add_count(app, "--repeat", o.repeat, 1, 1000, "runs (default 0: 1; 3 with --ccd-both or --filters compare)");
  app.add_option("--filters", o.filters,
                 "collision filters given to every sphere: accept-all (filtered, nothing rejected), teams (two "
                 "teams that pass through each other); compare: runs none, accept-all and teams in turn, one table")
      ->check(CLI::IsMember({"none", "accept-all", "teams", "compare"}));
  app.add_option("--json", o.json_path, "every figure of the (last) run as JSON")->type_name("FILE");
  app.add_option("--trace", o.trace_path,
                 "Chrome trace-event JSON (Perfetto) of the last run: a slice per phase per step per thread")
      ->type_name("FILE");
  app.add_option("--dump-state", o.dump_state_path, "every sphere's final state: id,x,y,z,vx,vy,vz,wx,wy,wz")
      ->type_name("FILE.csv");
  add_count(app, "--dump-every", o.dump_every, 1, 100'000'000,
            "with --dump-state: also the state at step 0 and every N steps, to FILE-000060.csv (the step, 6 digits, "
            "before .csv)");
  add_number(app, "--memory-limit", o.memory_limit_gb, 0.0, 1e9,
             "GB; a sphere count over it is refused before anything is built (default -1: 80% of the memory available; "
             "0: none)");
  app.add_option_function<std::pair<int, std::string>>(
         "--save-at",
         [&o](const std::pair<int, std::string>& v) {
           if (v.first < 1) usage_error("--save-at STEP must be >= 1, got " + std::to_string(v.first));
           o.save_at = v.first, o.save_path = v.second;
         },
         "after step STEP, save a snapshot of the world to FILE (World::save_file; --restore reads it)")
      ->type_name("STEP FILE");
  app.add_option("--restore", o.restore_path,
                 "restore the world from a snapshot once the scene is built (the same scene and terrain), then step "
                 "it --steps more")
      ->type_name("FILE")
      ->check(CLI::ExistingFile);
  app.add_option("--expect-hash", o.expect_hash,
                 "exit status 1 unless the final state hash is H (16 hex digits, as printed): a run checked on "
                 "another machine")
      ->type_name("H");
  app.add_option("--record", o.record_path,
                 "record the (last) run: positions at step 0 and every --every K steps (docs/recording_format.md; "
                 "hail-view --replay plays it); untimed")
      ->type_name("FILE");
  add_count(app, "--every", o.record_every, 1, 100'000'000, "with --record: steps between frames");
  app.add_flag("--velocities", o.record_velocities, "with --record: frames carry velocities too");
  app.add_option("--vtk", o.vtk_dir,
                 "write ParaView frames of the (last) run into DIR: DIR/frame_000000.vtp at step 0 and every "
                 "--vtk-every K steps, and DIR/frame.pvd, their time index (docs/python.md); untimed")
      ->type_name("DIR");
  add_count(app, "--vtk-every", o.vtk_every, 1, 100'000'000, "with --vtk: steps between frames");
  app.add_flag("--quiet", o.quiet,
               "one summary line (scene, spheres, steps, ms/step, worst penetration, tunnelled, NaN, hash) and no "
               "progress lines on stderr; with --ccd-both, the table");
  // The checks between flags, once every flag is read.
  app.callback([&app, &o] {
    if (o.home_after > 0 && o.origin == 0.0)
      usage_error("--home-after K needs --origin D (a scene moved out to bring home)");
    if (o.params.terrain_as_mesh && (!o.scene_file.empty() || o.scene == "implosion"))
      usage_error(
          "--terrain-as-mesh applies to the built-in scenes on a heightmap (terrain-rain, bowl-pile, "
          "terrain-rain-dem, bullets), not to " +
          (o.scene_file.empty() ? o.scene : std::string("--scene")));
    for (const char* flag : {"--spheres", "--threads", "--steps", "--dt"})
      if (app.count(flag) > 0) o.given.emplace_back(flag);
    o.given_settings = given_setting_flags(app, o.params.settings);
    o.scene_named = app.count("scene") > 0;
    if (o.dump_every > 0 && o.dump_state_path.empty())
      usage_error("--dump-every " + std::to_string(o.dump_every) +
                  " needs --dump-state FILE.csv (the files are named after it)");
    if (o.ccd_both && app.count("--ccd") > 0) usage_error("--ccd-both runs with --ccd on and off: give one of them");
    if (o.ccd_both && (o.save_at > 0 || !o.restore_path.empty() || !o.expect_hash.empty() || !o.record_path.empty()))
      usage_error("--save-at, --restore, --expect-hash and --record take one world: not with --ccd-both");
    if (o.record_path.empty() && (app.count("--every") > 0 || o.record_velocities))
      usage_error("--every and --velocities need --record FILE");
    if (!o.record_path.empty() && o.filters == "compare")
      usage_error("--record takes one world: not with --filters compare");
    if (o.save_at > 0 && o.save_path == o.restore_path)
      usage_error("--save-at would overwrite the --restore snapshot '" + o.save_path + "'");
    // A snapshot holds every setting of the world it saved (all but threads) and every sphere's
    // filter bits: these flags would be overwritten by it, so a run would report one thing and
    // step another. They belong to the run that saves it.
    if (!o.restore_path.empty()) {
      std::vector<std::string> flags = setting_flags();
      flags.emplace_back("--set");
      for (const std::string& flag : flags)
        if (app.count(flag) > 0)
          usage_error(std::string("--restore takes the world's settings from the snapshot: ") + flag +
                      " would be ignored (give it to the run that saves the snapshot)");
      if (o.filters != "none")
        usage_error("--restore takes every sphere's collision filter from the snapshot: --filters " + o.filters +
                    " would be ignored (give it to the run that saves the snapshot)");
    }
    if (o.scene_named && !o.scene_file.empty())
      usage_error("give a scene name or --scene FILE.json, not both ('" + o.scene + "' and '" + o.scene_file + "')");
  });
}

int run_command(const std::vector<std::string>& args) {
  const std::optional<RunCommandOptions> parsed = parse_command("run", add_run_options, args);
  return parsed ? run_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
