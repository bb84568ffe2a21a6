#include "scenes/scene_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

#include "scenes/machine_info.h"
#include "scenes/memory_use.h"
#include "scenes/output_file.h"

namespace hail::bench {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// Chrome trace-event JSON (opens in Perfetto and chrome://tracing): one complete ("X") event
/// per phase per step per thread, threads named "arena slot k".
void write_trace(const std::string& path, const PhaseTrace& trace, int threads) {
  nlohmann::json events = nlohmann::json::array();
  for (int t = 0; t < threads; ++t)
    events.push_back({{"name", "thread_name"},
                      {"ph", "M"},
                      {"pid", 1},
                      {"tid", t},
                      {"args", {{"name", "arena slot " + std::to_string(t)}}}});
  for (const TraceSlice& s : trace.slices())
    events.push_back({{"name", phase_name(s.phase)},
                      {"cat", "step"},
                      {"ph", "X"},
                      {"pid", 1},
                      {"tid", s.thread},
                      {"ts", s.start_us},
                      {"dur", s.end_us - s.start_us},
                      {"args", {{"step", s.step}}}});
  write_file_atomically(path, [&](std::ostream& out) {
    out << nlohmann::json{{"traceEvents", events}, {"displayTimeUnit", "ms"}}.dump() << "\n";
  });
}

void add(PhaseTimes& sum, const PhaseTimes& t, double weight) {
  sum.reorder += weight * t.reorder;
  sum.predict += weight * t.predict;
  sum.detect_terrain += weight * t.detect_terrain;
  sum.detect_pairs += weight * t.detect_pairs;
  sum.solve += weight * t.solve;
  sum.sweep += weight * t.sweep;
  sum.integrate += weight * t.integrate;
  sum.depenetrate += weight * t.depenetrate;
  sum.islands += weight * t.islands;
}

}  // namespace

std::string hex_hash(std::uint64_t h) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

const SceneEntry& find_scene(const std::string& name) {
  const auto& registry = scene_registry();
  const auto entry =
      std::find_if(registry.begin(), registry.end(), [&](const SceneEntry& e) { return name == e.name; });
  if (entry == registry.end()) {
    std::string names;
    for (const auto& e : registry) names += std::string(names.empty() ? "" : ", ") + e.name;
    throw std::invalid_argument("unknown scene '" + name + "' (known: " + names + ")");
  }
  return *entry;
}

RunResult run_scene(const SceneEntry& entry, const SceneParams& params, const RunOptions& options) {
  return run_scene(
      entry.name, [&] { return entry.build(params); }, options);
}

std::string step_dump_path(const std::string& path, int step) {
  const std::filesystem::path p(path);
  char number[32];
  std::snprintf(number, sizeof number, "-%06d", step);
  std::filesystem::path name = p.stem();
  name += number;
  name += p.extension();
  return (p.parent_path() / name).string();
}

void write_state_csv(const Scene& scene, const std::string& path) {
  const World& world = *scene.world;
  if (scene.ids.size() != world.sphere_count())
    throw std::runtime_error("cannot write " + path + ": the scene recorded " + std::to_string(scene.ids.size()) +
                             " sphere handles for " + std::to_string(world.sphere_count()) + " spheres");
  write_file_atomically(path, [&](std::ostream& out) {
    out << "id,x,y,z,vx,vy,vz,wx,wy,wz\n";
    char row[256];
    for (std::size_t k = 0; k < scene.ids.size(); ++k) {
      const Vec3 x = world.position(scene.ids[k]), v = world.velocity(scene.ids[k]),
                 w = world.angular_velocity(scene.ids[k]);
      std::snprintf(row, sizeof row, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", k, x.x(), x.y(), x.z(),
                    v.x(), v.y(), v.z(), w.x(), w.y(), w.z());
      out << row;
    }
  });
}

namespace {

void count_parts(const StepParts& ran, RunResult::PartCounts& count) {
  count.reorder += ran.reorder, count.detect_static += ran.detect_static, count.detect_pairs += ran.detect_pairs;
  count.solve += ran.solve, count.friction += ran.friction, count.rotation += ran.rotation, count.shock += ran.shock;
  count.sweep += ran.sweep;
  count.depenetrate += ran.depenetrate, count.terrain_guard += ran.terrain_guard;
}

/// (name, steps it ran in) for each optional part, in step order.
std::vector<std::pair<const char*, int>> part_list(const RunResult::PartCounts& c) {
  return {{"reorder", c.reorder},
          {"detect-static", c.detect_static},
          {"detect-pairs", c.detect_pairs},
          {"solve", c.solve},
          {"friction", c.friction},
          {"rotation", c.rotation},
          {"shock", c.shock},
          {"sweep", c.sweep},
          {"depenetrate", c.depenetrate},
          {"terrain-guard", c.terrain_guard}};
}

}  // namespace

std::string describe_parts(const RunResult& r) {
  std::string ran = "ran ", skipped;
  for (const auto& [name, steps] : part_list(r.parts_ran)) {
    if (std::string_view(name) == "detect-static") ran.append("predict, ");  // always runs, after reorder
    if (steps == 0) {
      if (!skipped.empty()) skipped.append(", ");
      skipped.append(name);
      continue;
    }
    ran.append(name);
    if (steps < r.steps)
      ran.append(" (").append(std::to_string(steps)).append("/").append(std::to_string(r.steps)).append(" steps)");
    ran.append(", ");
  }
  ran.append("integrate; skipped: ").append(skipped.empty() ? "nothing" : skipped);
  return ran;
}

RunResult run_scene(const std::string& name, const std::function<Scene()>& build, const RunOptions& options) {
  using clock = std::chrono::steady_clock;
  RunResult r;
  const std::optional<std::size_t> heap_before = heap_bytes_in_use();
  // The heap the run added since heap_before (0 if it shrank: another thread freed meanwhile).
  auto heap_added = [&] {
    const std::optional<std::size_t> now = heap_bytes_in_use();
    return now && heap_before && *now > *heap_before ? *now - *heap_before : std::size_t{0};
  };
  const auto setup_start = clock::now();
  Scene scene = build();
  r.setup_s = std::chrono::duration<double>(clock::now() - setup_start).count();
  World& world = *scene.world;
  r.heap_measured = heap_before.has_value();
  r.heap_after_setup = heap_added();
  r.terrain_bytes = world.terrain() != nullptr ? world.terrain()->memory_bytes() : 0;
  r.scene = name;
  r.description = scene.description;
  r.spheres = world.sphere_count();
  r.threads = world.thread_count();
  r.steps = options.steps > 0 ? options.steps : scene.default_steps;
  r.warmup = r.steps > 120 ? 60 : 0;  // the scenes' definition: report steps 60..599
  r.dt = scene.dt;
  r.reorder_interval = world.settings().reorder_interval;
  r.warm_start_factor = world.settings().warm_start_factor;
  r.continuous_collision = world.settings().continuous_collision;
  if (const WorldSettings& ws = world.settings(); ws.solver == Solver::SoftStep) {
    char text[128];
    std::snprintf(text, sizeof text,
                  "soft (%d substeps, %g cycles, damping %g, %d relax, up to %d depenetration passes)",
                  ws.soft_step.substeps, double(ws.soft_step.contact_cycles), double(ws.soft_step.damping_ratio),
                  ws.soft_step.relax_iterations,
                  std::max(ws.depenetration_iterations, ws.soft_step.depenetration_iterations_max));
    r.solver = text;
  } else {
    r.solver = "passes";
  }
  r.tunnelling_checked = world.terrain() != nullptr || !world.planes().empty();

  if (!options.trace_path.empty()) world.enable_trace(true);
  r.energy_start = r.energy_peak = world.kinetic_energy();
  const bool dump_steps = options.dump_every > 0 && !options.dump_state_path.empty();
  if (dump_steps) write_state_csv(scene, step_dump_path(options.dump_state_path, 0));
  const Eigen::Vector3d momentum_start = world.linear_momentum();
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(r.steps));
  const double weight = 1.0 / static_cast<double>(r.steps - r.warmup);
  auto last_progress = clock::now();
  const auto run_start = clock::now();
  TunnellingCounter tunnelling;
  double worst_sphere = 0.0, worst_static = 0.0;  // ErrorFigures::worst_*_penetration
  double mean_sphere = 0.0, mean_static = 0.0;    // ErrorFigures::mean_step_*_penetration
  for (int k = 0; k < r.steps; ++k) {
    const auto t0 = clock::now();
    world.step(scene.dt);
    step_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    if (options.after_step) options.after_step(scene, k + 1);
    // Untimed, as every figure below: a pass over the spheres each, part of the error report.
    tunnelling.after_step(world);
    if (const double energy = world.kinetic_energy(); energy > r.energy_peak)
      r.energy_peak = energy, r.energy_peak_step = k + 1;
    if (dump_steps && (k + 1) % options.dump_every == 0)
      write_state_csv(scene, step_dump_path(options.dump_state_path, k + 1));
    if (k >= r.warmup) {
      double deepest_sphere = 0.0, deepest_static = 0.0;
      for (const Contact& c : world.last_contacts()) {  // untimed, like the tunnelling check
        double& deepest = c.b == kStaticBody ? deepest_static : deepest_sphere;
        deepest = std::max(deepest, -static_cast<double>(c.gap));
      }
      worst_sphere = std::max(worst_sphere, deepest_sphere), worst_static = std::max(worst_static, deepest_static);
      mean_sphere += weight * deepest_sphere, mean_static += weight * deepest_static;
      add(r.phase_ms, world.last_phase_times(), weight);
      const StepStats& stats = world.last_step_stats();
      r.static_contacts += weight * double(stats.static_contacts);
      r.sphere_contacts += weight * double(stats.sphere_contacts);
      r.warm_started += weight * double(stats.warm_started);
      r.colours += weight * double(stats.colours);
      r.tile_contacts += weight * double(stats.tile_contacts);
      r.shared_contacts += weight * double(stats.shared_contacts);
      r.parallel_loops += weight * double(stats.parallel_loops);
      r.crew_stages += weight * double(stats.crew_stages);
      r.collision_passes += weight * stats.collision_passes;
      r.depenetration_passes += weight * stats.depenetration_passes;
      r.swept += weight * double(stats.sweep.swept);
      r.swept_meeting_spheres += weight * double(stats.sweep.meets_spheres);
      r.sweep_events += weight * double(stats.sweep.events);
      r.sleeping += weight * double(stats.sleeping);
      r.ready_to_sleep += weight * double(stats.ready_to_sleep);
    }
    r.sweep_capped += world.last_step_stats().sweep.capped;
    r.sweep_held += world.last_step_stats().sweep.held;
    count_parts(world.last_step_stats().ran, r.parts_ran);
    if (options.progress && clock::now() - last_progress > std::chrono::seconds(2)) {
      std::fprintf(stderr, "  %sstep %d/%d, %.2f ms/step so far\n", options.progress_label.c_str(), k + 1, r.steps,
                   std::accumulate(step_ms.begin(), step_ms.end(), 0.0) / static_cast<double>(step_ms.size()));
      last_progress = clock::now();
    }
  }
  r.total_s = std::chrono::duration<double>(clock::now() - run_start).count();
  const std::vector<double> timed(step_ms.begin() + r.warmup, step_ms.end());
  r.mean_ms = std::accumulate(timed.begin(), timed.end(), 0.0) / static_cast<double>(timed.size());
  r.median_ms = median(timed);
  r.heap_at_end = heap_added();
  r.memory_parts = world.memory_use();
  r.errors = measure_errors(scene);
  r.tunnelling = tunnelling.figures();
  r.errors.worst_sphere_penetration = worst_sphere;
  r.errors.worst_static_penetration = worst_static;
  r.errors.mean_step_sphere_penetration = mean_sphere;
  r.errors.mean_step_static_penetration = mean_static;
  r.momentum_drift = (world.linear_momentum() - momentum_start).norm();
  r.energy_drift = r.energy_start > 0 ? (r.errors.kinetic_energy - r.energy_start) / r.energy_start : 0.0;
  // The NaN count covers every figure printed, not only the state: finite positions and
  // velocities with a broken mass gave a NaN energy while the run reported "NaN 0".
  for (double figure :
       {r.errors.worst_sphere_penetration, r.errors.worst_static_penetration, r.errors.mean_step_sphere_penetration,
        r.errors.mean_step_static_penetration, r.momentum_drift, r.energy_drift, r.energy_start, r.energy_peak})
    r.errors.nan_count += std::isfinite(figure) ? 0 : 1;
  r.state_hash = hex_hash(world.state_hash());
  r.sleep = world.settings().sleep;
  r.sleeping_at_end = world.last_step_stats().sleeping;
  r.ready_to_sleep_at_end = world.last_step_stats().ready_to_sleep;
  constexpr const char* kPairSearchNames[] = {"auto", "brute force", "grid", "sweep and prune", "sphere BVH"};
  r.pair_search = kPairSearchNames[static_cast<int>(world.last_step_stats().pair_search)];
  if (!options.trace_path.empty()) write_trace(options.trace_path, world.trace(), world.thread_count());
  if (!options.dump_state_path.empty()) write_state_csv(scene, options.dump_state_path);
  return r;
}

namespace {
/// World::memory_use by part, and the total: JSON memory.parts_bytes.
nlohmann::json parts_bytes(const MemoryUse& m) {
  nlohmann::json parts = nlohmann::json::object();
  m.for_each_part([&](const char* name, std::size_t bytes) { parts[name] = bytes; });
  parts["total"] = m.total();
  return parts;
}
}  // namespace

nlohmann::json to_json(const RunResult& r) {
  const ErrorFigures& e = r.errors;
  const PhaseTimes& p = r.phase_ms;
  return {
      {"scene", r.scene},
      {"spheres", r.spheres},
      {"threads", r.threads},
      {"steps", r.steps},
      {"timed_steps_from", r.warmup},
      {"dt", r.dt},
      {"reorder_interval", r.reorder_interval},
      {"solver", r.solver},
      {"ms_per_step_mean", r.mean_ms},
      {"ms_per_step_median", r.median_ms},
      {"ns_per_sphere_step", 1e6 * r.mean_ms / double(std::max<std::size_t>(r.spheres, 1))},
      {"total_s", r.total_s},
      {"setup_s", r.setup_s},
      {"max_penetration", std::max(e.max_sphere_penetration, e.max_terrain_penetration)},
      {"max_sphere_penetration", e.max_sphere_penetration},
      {"max_terrain_penetration", e.max_terrain_penetration},
      {"worst_sphere_penetration", e.worst_sphere_penetration},
      {"worst_static_penetration", e.worst_static_penetration},
      {"mean_step_sphere_penetration", e.mean_step_sphere_penetration},
      {"mean_step_static_penetration", e.mean_step_static_penetration},
      {"tunnelled", e.tunnelled},
      {"tunnelled_ever", r.tunnelling.spheres},
      {"tunnelling",
       {{"checked", r.tunnelling_checked},
        {"events", r.tunnelling.events},
        {"spheres", r.tunnelling.spheres},
        {"worst_depth", r.tunnelling.worst_depth},
        {"steps_checked", r.tunnelling.steps}}},
      {"fell_off", e.fell_off},
      {"kinetic_energy", e.kinetic_energy},
      {"kinetic_energy_start", r.energy_start},
      {"kinetic_energy_peak", r.energy_peak},
      {"kinetic_energy_peak_step", r.energy_peak_step},
      {"momentum_drift", r.momentum_drift},
      {"energy_drift", r.energy_drift},
      {"nan_count", e.nan_count},
      {"state_hash", r.state_hash},
      {"memory",
       {{"parts_bytes", parts_bytes(r.memory_parts)},
        {"heap_after_setup_bytes", r.heap_after_setup},
        {"heap_at_end_bytes", r.heap_at_end},
        {"terrain_bytes", r.terrain_bytes},
        {"bytes_per_sphere", r.bytes_per_sphere()},
        {"measured", r.heap_measured}}},
      {"pair_search", r.pair_search},
      {"phases_ms",
       {{"reorder", p.reorder},
        {"predict", p.predict},
        {"detect_terrain", p.detect_terrain},
        {"detect_pairs", p.detect_pairs},
        {"solve", p.solve},
        {"sweep", p.sweep},
        {"integrate", p.integrate},
        {"depenetrate", p.depenetrate},
        {"islands", p.islands}}},
      {"sleep",
       {{"on", r.sleep},
        {"sleeping_mean", r.sleeping},
        {"ready_to_sleep_mean", r.ready_to_sleep},
        {"sleeping_at_end", r.sleeping_at_end},
        {"ready_to_sleep_at_end", r.ready_to_sleep_at_end}}},
      {"phases_ran_steps",
       [&] {
         nlohmann::json parts = nlohmann::json::object();
         for (const auto& [part, steps] : part_list(r.parts_ran)) parts[part] = steps;
         return parts;
       }()},
      {"warm_start_factor", r.warm_start_factor},
      {"solver_per_step",
       {{"static_contacts", r.static_contacts},
        {"sphere_contacts", r.sphere_contacts},
        {"warm_started", r.warm_started},
        {"colours", r.colours},
        {"tile_contacts", r.tile_contacts},
        {"shared_contacts", r.shared_contacts},
        {"collision_passes", r.collision_passes},
        {"depenetration_passes", r.depenetration_passes},
        {"parallel_loops", r.parallel_loops},
        {"crew_stages", r.crew_stages}}},
      {"continuous_collision",
       {{"on", r.continuous_collision},
        {"swept_per_step", r.swept},
        {"swept_meeting_spheres_per_step", r.swept_meeting_spheres},
        {"impacts_per_step", r.sweep_events},
        {"capped_total", r.sweep_capped},
        {"held_total", r.sweep_held}}},
      {"machine",
       {{"cpu", cpu_model()},
        {"simd", simd_path()},
        {"simd_chosen_by", simd_origin()},
        {"simd_supported", simd_supported()},
        {"simd_flags", simd_flags()},
        {"flags", build_flags()}}},
  };
}

}  // namespace hail::bench
