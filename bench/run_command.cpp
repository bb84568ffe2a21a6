#include "run_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <stdexcept>

#include "machine_info.h"
#include "metrics.h"
#include "scenes.h"

namespace hail::bench {
namespace {

struct RunOptions {
  std::string scene = "implosion";
  SceneParams params;
  int steps = -1;  // -1: the scene's default
  std::string json_path;
  std::string trace_path;
  bool quiet = false;
};

[[noreturn]] void usage_error(const std::string& message) { throw std::invalid_argument(message); }

template <class T>
T parse_number(const std::string& flag, const std::string& text) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument("trailing characters");
    return static_cast<T>(value);
  } catch (const std::exception&) {
    usage_error(flag + " expects a number, got '" + text + "'");
  }
}

RunOptions parse(const std::vector<std::string>& args) {
  RunOptions o;
  std::size_t k = 0;
  if (k < args.size() && args[k].rfind("--", 0) != 0) o.scene = args[k++];
  for (; k < args.size(); ++k) {
    const std::string& flag = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) usage_error(flag + " needs a value");
      return args[++k];
    };
    if (flag == "--spheres") {
      const double n = parse_number<double>(flag, value());
      if (!(n >= 1 && n <= 1e8)) usage_error("--spheres must be in [1, 1e8]");
      o.params.spheres = static_cast<std::size_t>(n);
    } else if (flag == "--steps") {
      o.steps = parse_number<int>(flag, value());
      if (o.steps < 1) usage_error("--steps must be >= 1");
    } else if (flag == "--threads") {
      o.params.threads = parse_number<int>(flag, value());
      if (o.params.threads < 0) usage_error("--threads must be >= 0 (0 = all)");
    } else if (flag == "--dt") {
      o.params.dt = parse_number<float>(flag, value());
      if (!(o.params.dt > 0 && o.params.dt < 10)) usage_error("--dt must be in (0, 10) s");
    } else if (flag == "--reorder") {
      o.params.reorder_interval = parse_number<int>(flag, value());
      if (o.params.reorder_interval < 0) usage_error("--reorder must be >= 0 (steps between Morton re-sorts; 0 = never)");
    } else if (flag == "--trace") {
      o.trace_path = value();
    } else if (flag == "--json") {
      o.json_path = value();
    } else if (flag == "--quiet") {
      o.quiet = true;
    } else {
      usage_error("unknown option '" + flag + "' (see hail-bench --help)");
    }
  }
  return o;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string hex(std::uint64_t h) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

/// Chrome trace-event JSON (opens in Perfetto and chrome://tracing): one complete ("X") event
/// per phase per step per thread, threads named "arena slot k".
void write_trace(const std::string& path, const PhaseTrace& trace, int threads) {
  nlohmann::json events = nlohmann::json::array();
  for (int t = 0; t < threads; ++t)
    events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", 1}, {"tid", t},
                      {"args", {{"name", "arena slot " + std::to_string(t)}}}});
  for (const TraceSlice& s : trace.slices())
    events.push_back({{"name", phase_name(s.phase)}, {"cat", "step"}, {"ph", "X"}, {"pid", 1}, {"tid", s.thread},
                      {"ts", s.start_us}, {"dur", s.end_us - s.start_us}, {"args", {{"step", s.step}}}});
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << nlohmann::json{{"traceEvents", events}, {"displayTimeUnit", "ms"}}.dump() << "\n";
}

}  // namespace

int run_command(const std::vector<std::string>& args) {
  const RunOptions o = parse(args);
  const auto& registry = scene_registry();
  const auto entry = std::find_if(registry.begin(), registry.end(), [&](const SceneEntry& e) { return o.scene == e.name; });
  if (entry == registry.end()) {
    std::string names;
    for (const auto& e : registry) names += std::string(names.empty() ? "" : ", ") + e.name;
    usage_error("unknown scene '" + o.scene + "' (known: " + names + ")");
  }

  using clock = std::chrono::steady_clock;
  const auto setup_start = clock::now();
  Scene scene = entry->build(o.params);
  const double setup_s = std::chrono::duration<double>(clock::now() - setup_start).count();
  World& world = *scene.world;
  const int steps = o.steps > 0 ? o.steps : scene.default_steps;

  if (!o.trace_path.empty()) world.enable_trace(true);
  const double energy_start = world.kinetic_energy();
  const Eigen::Vector3d momentum_start = world.linear_momentum();
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(steps));
  PhaseTimes phase_sum;
  double static_contacts = 0, sphere_contacts = 0, colours = 0, collision_passes = 0;  // sums over timed steps
  const int warmup = steps > 120 ? 60 : 0;  // the scene's definition: report steps 60..599
  auto last_progress = clock::now();
  const auto run_start = clock::now();
  for (int k = 0; k < steps; ++k) {
    const auto t0 = clock::now();
    world.step(o.params.dt);
    step_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    if (k >= warmup) {
      const PhaseTimes& t = world.last_phase_times();
      phase_sum.reorder += t.reorder;
      phase_sum.predict += t.predict;
      phase_sum.detect_terrain += t.detect_terrain;
      phase_sum.detect_pairs += t.detect_pairs;
      phase_sum.solve += t.solve;
      phase_sum.integrate += t.integrate;
      phase_sum.depenetrate += t.depenetrate;
      const StepStats& stats = world.last_step_stats();
      static_contacts += double(stats.static_contacts);
      sphere_contacts += double(stats.sphere_contacts);
      colours += double(stats.colours);
      collision_passes += stats.collision_passes;
    }
    if (!o.quiet && clock::now() - last_progress > std::chrono::seconds(2)) {
      std::fprintf(stderr, "  step %d/%d, %.2f ms/step so far\n", k + 1, steps,
                   std::accumulate(step_ms.begin(), step_ms.end(), 0.0) / static_cast<double>(step_ms.size()));
      last_progress = clock::now();
    }
  }
  const double total_s = std::chrono::duration<double>(clock::now() - run_start).count();
  const std::vector<double> timed(step_ms.begin() + warmup, step_ms.end());
  const double mean = std::accumulate(timed.begin(), timed.end(), 0.0) / static_cast<double>(timed.size());
  const double med = median(timed);
  const ErrorFigures errors = measure_errors(scene);
  const double momentum_drift = (world.linear_momentum() - momentum_start).norm();
  const double energy_drift = energy_start > 0 ? (errors.kinetic_energy - energy_start) / energy_start : 0.0;
  const double per_step = 1.0 / static_cast<double>(timed.size());
  const std::string hash = hex(world.state_hash());

  std::printf("hail-bench run %s  (%s)\n", o.scene.c_str(), scene.description.c_str());
  std::printf("  machine   %s, %d threads, SIMD %s\n", cpu_model().c_str(), world.thread_count(), simd_path().c_str());
  std::printf("  scene     %zu spheres, %d steps of dt = %.6g s, Morton re-sort every %d steps\n", world.sphere_count(), steps,
              o.params.dt, o.params.reorder_interval);
  std::printf("  time      %.3f ms/step mean, %.3f median (steps %d..%d), total %.3f s, set-up %.3f s\n", mean, med,
              warmup, steps - 1, total_s, setup_s);
  std::printf("  phases    reorder %.3f  predict %.3f  detect-terrain %.3f  detect-pairs %.3f  solve %.3f  integrate %.3f  depenetrate %.3f ms\n",
              phase_sum.reorder * per_step, phase_sum.predict * per_step, phase_sum.detect_terrain * per_step, phase_sum.detect_pairs * per_step,
              phase_sum.solve * per_step, phase_sum.integrate * per_step, phase_sum.depenetrate * per_step);
  std::printf("  solver    per step: %.0f static + %.0f sphere contacts, %.1f colours, %.2f collision passes that applied an impulse\n",
              static_contacts * per_step, sphere_contacts * per_step, colours * per_step, collision_passes * per_step);
  std::printf("  error     max penetration %.4g m (spheres) %.4g m (ground), tunnelled %zu, fell off %zu, NaN %zu\n",
              errors.max_sphere_penetration, errors.max_terrain_penetration, errors.tunnelled, errors.fell_off,
              errors.nan_count);
  std::printf("  energy    kinetic %.6g J (start %.6g J, drift %+.3e), momentum drift %.3e kg m/s\n",
              errors.kinetic_energy, energy_start, energy_drift, momentum_drift);
  std::printf("  state     hash %s\n", hash.c_str());

  if (!o.trace_path.empty()) {
    write_trace(o.trace_path, world.trace(), world.thread_count());
    std::printf("  trace     %zu slices written to %s (open in https://ui.perfetto.dev or chrome://tracing)\n",
                world.trace().slices().size(), o.trace_path.c_str());
  }
  if (!o.json_path.empty()) {
    nlohmann::json j = {
        {"scene", o.scene},
        {"spheres", world.sphere_count()},
        {"threads", world.thread_count()},
        {"steps", steps},
        {"dt", o.params.dt},
        {"reorder_interval", o.params.reorder_interval},
        {"ms_per_step_mean", mean},
        {"ms_per_step_median", med},
        {"total_s", total_s},
        {"setup_s", setup_s},
        {"max_penetration", std::max(errors.max_sphere_penetration, errors.max_terrain_penetration)},
        {"max_sphere_penetration", errors.max_sphere_penetration},
        {"max_terrain_penetration", errors.max_terrain_penetration},
        {"tunnelled", errors.tunnelled},
        {"fell_off", errors.fell_off},
        {"kinetic_energy", errors.kinetic_energy},
        {"kinetic_energy_start", energy_start},
        {"momentum_drift", momentum_drift},
        {"energy_drift", energy_drift},
        {"nan_count", errors.nan_count},
        {"state_hash", hash},
        {"phases_ms", {{"reorder", phase_sum.reorder * per_step},
                       {"predict", phase_sum.predict * per_step},
                       {"detect_terrain", phase_sum.detect_terrain * per_step},
                       {"detect_pairs", phase_sum.detect_pairs * per_step},
                       {"solve", phase_sum.solve * per_step},
                       {"integrate", phase_sum.integrate * per_step},
                       {"depenetrate", phase_sum.depenetrate * per_step}}},
        {"solver_per_step", {{"static_contacts", static_contacts * per_step},
                             {"sphere_contacts", sphere_contacts * per_step},
                             {"colours", colours * per_step},
                             {"collision_passes", collision_passes * per_step}}},
        {"machine", {{"cpu", cpu_model()}, {"simd", simd_path()}, {"flags", build_flags()}}},
    };
    std::ofstream out(o.json_path);
    if (!out) throw std::runtime_error("cannot write " + o.json_path);
    out << j.dump(2) << "\n";
  }
  return errors.nan_count == 0 ? 0 : 3;
}

}  // namespace hail::bench
