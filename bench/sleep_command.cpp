#include "sleep_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "cli.h"
#include "gnuplot.h"
#include "parse_numbers.h"
#include "scenes/machine_info.h"
#include "scenes/output_file.h"
#include "scenes/scene_run.h"

namespace hail::bench {
namespace {

std::vector<std::size_t> parse_sizes(const std::string& text) {
  const std::vector<long long> counts = parse_count_list("--sizes entry", text, 1, 100'000'000);
  return {counts.begin(), counts.end()};
}

/// One sample of a run, taken after every --every-th step.
struct Sample {
  int step = 0;
  double asleep_share = 0, kinetic_energy = 0;
  double deepest_sphere = 0, deepest_static = 0;  ///< m, that step's deepest overlaps
};

struct SleepRun {
  RunResult result;
  std::vector<Sample> samples;
};

SleepRun run_sampled(const SceneEntry& entry, SceneParams params, bool sleep, const SleepOptions& o) {
  params.settings.sleep = sleep;
  SleepRun run;
  RunOptions options;
  options.steps = o.steps;
  options.progress_label = std::to_string(params.spheres) + (sleep ? " sleep on: " : " sleep off: ");
  options.after_step = [&](Scene& scene, int step) {
    if (step % o.every != 0) return;
    const World& w = *scene.world;
    Sample s{.step = step};
    s.asleep_share = double(w.last_step_stats().sleeping) / double(std::max<std::size_t>(w.sphere_count(), 1));
    s.kinetic_energy = w.kinetic_energy();
    for (const Contact& c : w.last_contacts()) {
      double& deepest = c.b == kStaticBody ? s.deepest_static : s.deepest_sphere;
      deepest = std::max(deepest, -static_cast<double>(c.gap));
    }
    run.samples.push_back(s);
  };
  run.result = run_scene(entry, params, options);
  return run;
}

void print_row(const char* label, const RunResult& r) {
  const ErrorFigures& e = r.errors;
  std::printf("%9zu %5s %9.3f %9.3f %6.1f%% %6.1f%% %8zu | %9.6f %9.6f %9.6f %9.6f %5zu %5zu %4zu %10.4g %s\n",
              r.spheres, label, r.mean_ms, r.median_ms, 100.0 * r.sleeping / double(r.spheres),
              100.0 * double(r.sleeping_at_end) / double(r.spheres), r.ready_to_sleep_at_end,
              e.worst_sphere_penetration, e.worst_static_penetration, e.mean_step_sphere_penetration,
              e.mean_step_static_penetration, r.tunnelling.spheres, e.fell_off, e.nan_count, e.kinetic_energy,
              r.state_hash.c_str());
  std::fflush(stdout);
}

const char* kGnuplotScript =
    R"(# hail-bench sleep: the share of spheres asleep over simulated time, one line per sphere count.
set terminal svg size 900,420 dynamic font 'sans,11'
set key bottom right
set grid
set output 'asleep_share.svg'
set xlabel 'simulated time (s)'
set ylabel 'spheres asleep (%)'
set yrange [0:100]
set title TITLE
set datafile separator ','
plot for [k=1:COUNTS] sprintf('asleep-%s.csv', word(SIZES, k)) using 2:(100 * $3) every ::1 with lines title sprintf('%s spheres', word(SIZES, k))
)";

/// Part 1: the scene with sleeping off and on at each size.
int compare_sizes(const SleepOptions& o, const std::vector<std::size_t>& sizes) {
  const SceneEntry& entry = find_scene(o.scene);
  std::printf("# part 1: %s, %d steps, sleeping off then on at each count, %d threads\n", o.scene.c_str(), o.steps,
              o.threads);
  std::printf(
      "# asleep: mean share over the timed steps / share at the end; ready: awake spheres slow for sleep_time at the "
      "end (held awake by their island);\n"
      "# worst: deepest overlap any step started from, spheres / ground (m); mean: each step's deepest, averaged;\n"
      "# tunnelled: spheres whose centre ever ended a step inside the ground; KE at the end (J)\n");
  std::printf("%9s %5s %9s %9s %7s %7s %8s | %9s %9s %9s %9s %5s %5s %4s %10s %s\n", "spheres", "sleep", "mean_ms",
              "median_ms", "asleep", "at_end", "ready", "worst_sph", "worst_gnd", "mean_sph", "mean_gnd", "tunl",
              "fell", "NaN", "KE", "hash");
  int status = 0;
  std::string size_words;
  for (const std::size_t n : sizes) {
    SceneParams params;
    params.spheres = n;
    params.threads = o.threads;
    const SleepRun off = run_sampled(entry, params, false, o);
    print_row("off", off.result);
    const SleepRun on = run_sampled(entry, params, true, o);
    print_row("on", on.result);
    std::printf("%9s %5s %8.2fx %8.2fx  (off / on)\n", "", "", off.result.mean_ms / on.result.mean_ms,
                off.result.median_ms / on.result.median_ms);
    if (off.result.errors.nan_count + on.result.errors.nan_count > 0) status = 3;
    write_file_atomically(o.out_dir + "/asleep-" + std::to_string(n) + ".csv", [&](std::ostream& csv) {
      csv << "step,time_s,asleep_share,ke_on_J,ke_off_J,deepest_sphere_on_m,deepest_sphere_off_m,deepest_ground_on_m,"
             "deepest_ground_off_m\n";
      for (std::size_t k = 0; k < on.samples.size() && k < off.samples.size(); ++k) {
        const Sample &a = on.samples[k], &b = off.samples[k];
        csv << a.step << ',' << a.step * double(on.result.dt) << ',' << a.asleep_share << ',' << a.kinetic_energy << ','
            << b.kinetic_energy << ',' << a.deepest_sphere << ',' << b.deepest_sphere << ',' << a.deepest_static << ','
            << b.deepest_static << '\n';
      }
    });
    size_words += (size_words.empty() ? "" : " ") + std::to_string(n);
  }
  if (!o.no_plot) {
    write_file_atomically(o.out_dir + "/sleep.gp", [](std::ostream& gp) { gp << kGnuplotScript; });
    const std::string title = o.scene + ", " + std::to_string(o.threads) + " threads, on " + cpu_model();
    plot_with_gnuplot(
        o.out_dir, "sleep.gp",
        "TITLE=" + gnuplot_string(title) + "; SIZES='" + size_words + "'; COUNTS=" + std::to_string(sizes.size()),
        o.out_dir + "/asleep_share.svg");
  }
  return status;
}

/// How a settled pile answers a sphere dropped on it.
struct PileAnswer {
  std::vector<Vec3> before, moved;  ///< per pile sphere: position at the drop, displacement after
  double kinetic_energy = 0;        ///< J, the pile alone, at the end
  int asleep_steps = -1;            ///< steps until every sphere slept (sleeping on), -1: never
  int woke_after = -1;              ///< steps after the drop until the pile's first sphere woke
  std::size_t woke = 0;             ///< pile spheres awake at the end of that step
  std::size_t nan = 0;
};

/// bowl-pile of `o.drop_spheres`, stepped `settle` steps (sleeping on: until all sleep, at most
/// o.settle_steps, when `settle` < 0), then `delay` more, then a sphere of the pile's kind
/// dropped at 10 m/s from 3 m above the pile's top, then o.drop_steps steps.
PileAnswer drop_on_pile(const SleepOptions& o, bool sleep, int settle, int delay) {
  SceneParams params;
  params.spheres = static_cast<std::size_t>(o.drop_spheres);
  params.threads = o.threads;
  params.settings.sleep = sleep;
  Scene scene = find_scene("bowl-pile").build(params);
  World& w = *scene.world;
  PileAnswer a;
  int steps = 0;
  if (settle < 0) {
    while (steps < o.settle_steps && w.last_step_stats().sleeping < w.sphere_count()) w.step(scene.dt), ++steps;
    if (w.last_step_stats().sleeping == w.sphere_count()) a.asleep_steps = steps;
  } else {
    for (; steps < settle; ++steps) w.step(scene.dt);
  }
  for (int k = 0; k < delay; ++k) w.step(scene.dt);
  float top = -1e30f;
  for (const SphereId id : scene.ids) {
    a.before.push_back(w.position(id));
    top = std::max(top, a.before.back().y());
  }
  w.add_sphere({.position = {127.5f, top + 3.0f, 127.5f},
                .velocity = {0.0f, -10.0f, 0.0f},
                .radius = 0.5f,
                .restitution = 0.5f});
  for (int k = 1; k <= o.drop_steps; ++k) {
    w.step(scene.dt);
    if (sleep && a.woke_after < 0) {
      std::size_t awake = 0;
      for (const SphereId id : scene.ids) awake += !w.is_sleeping(id);
      if (awake > 0) a.woke_after = k, a.woke = awake;
    }
  }
  for (std::size_t k = 0; k < scene.ids.size(); ++k) {
    const Vec3 p = w.position(scene.ids[k]), v = w.velocity(scene.ids[k]);
    a.moved.push_back(p - a.before[k]);
    a.kinetic_energy += 0.5 * double(v.squaredNorm());  // the pile's spheres weigh 1 kg
  }
  a.nan = w.nan_count();
  return a;
}

/// Root mean square and largest of |x_k - y_k| over the pile (y empty: of |x_k|).
std::pair<double, double> rms_max(const std::vector<Vec3>& x, const std::vector<Vec3>& y = {}) {
  double sum = 0, worst = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const Vec3 d = y.empty() ? x[k] : Vec3(x[k] - y[k]);
    const double len = d.cast<double>().norm();
    sum += len * len, worst = std::max(worst, len);
  }
  return {std::sqrt(sum / double(std::max<std::size_t>(x.size(), 1))), worst};
}

/// Part 2: a sphere dropped on a sleeping pile against the same drop with sleeping off.
int compare_drop(const SleepOptions& o) {
  std::printf(
      "\n# part 2: bowl-pile of %d spheres settles with sleeping on until every sphere sleeps; the same pile with\n"
      "# sleeping off steps as many steps. A sphere (0.5 m, 1 kg) is dropped at 10 m/s from 3 m above the top, then\n"
      "# %d steps. The pile's answer: each pile sphere's displacement from where it was at the drop.\n"
      "# noise: the same drop one step later with sleeping off against the drop with sleeping off, so the\n"
      "# solver's own step-to-step variation; on vs off: sleeping on against sleeping off.\n",
      o.drop_spheres, o.drop_steps);
  const PileAnswer on = drop_on_pile(o, true, -1, 0);
  if (on.asleep_steps < 0) {
    std::printf("  the pile did not fall asleep within %d steps (--settle-steps): no comparison\n", o.settle_steps);
    return 1;
  }
  const PileAnswer off = drop_on_pile(o, false, on.asleep_steps, 0);
  const PileAnswer late = drop_on_pile(o, false, on.asleep_steps, 1);
  const auto [response_rms, response_max] = rms_max(off.moved);
  const auto [sleep_rms, sleep_max] = rms_max(on.moved, off.moved);
  const auto [noise_rms, noise_max] = rms_max(late.moved, off.moved);
  const auto [start_rms, start_max] = rms_max(on.before, off.before);
  std::printf("  every sphere asleep after %d steps; the pile woke %d step(s) after the drop (%zu of %d spheres)\n",
              on.asleep_steps, on.woke_after, on.woke, o.drop_spheres);
  std::printf("  pile at the drop, sleeping on vs off: positions differ by %.3g m RMS, %.3g m at most\n", start_rms,
              start_max);
  std::printf("  %-34s %12s %12s %14s\n", "displacement after the drop", "RMS (m)", "max (m)", "pile KE (J)");
  std::printf("  %-34s %12.4g %12.4g %14.4g\n", "the answer itself, sleeping off", response_rms, response_max,
              off.kinetic_energy);
  std::printf("  %-34s %12.4g %12.4g %14.4g\n", "sleeping on minus off", sleep_rms, sleep_max, on.kinetic_energy);
  std::printf("  %-34s %12.4g %12.4g %14.4g\n", "noise: off, one step later, minus off", noise_rms, noise_max,
              late.kinetic_energy);
  std::printf("  on vs off / noise: %.2f (RMS), %.2f (max)\n", sleep_rms / noise_rms, sleep_max / noise_max);
  return on.nan + off.nan + late.nan > 0 ? 3 : 0;
}

}  // namespace

int sleep_command(const SleepOptions& o) {
  const std::vector<std::size_t> sizes = parse_sizes(o.sizes);
  if (!sizes.empty()) prepare_output_dir(o.out_dir);  // a folder that cannot be written fails now
  std::printf("# hail-bench sleep: %s, simd %s\n", cpu_model().c_str(), simd_path().c_str());
  int status = 0;
  if (!sizes.empty()) status = compare_sizes(o, sizes);
  if (o.drop_spheres > 0) status = std::max(status, compare_drop(o));
  return status;
}

// The flags of `hail-bench sleep` (bench/cli.h's rules).

void add_sleep_options(CLI::App& app, SleepOptions& o) {
  app.description(
      "sleeping on against off: ms/step, spheres asleep and error figures side by side, the share asleep over time; "
      "then a sphere dropped on a sleeping pile against the same drop with sleeping off");
  app.add_option("scene", o.scene, "a built-in scene for part 1")->check(CLI::IsMember(scene_names()));
  app.add_option("--sizes", o.sizes, "part 1's sphere counts, comma-separated (empty: skip part 1)");
  add_count(app, "--steps", o.steps, 1, 100'000'000, "steps per part-1 run");
  add_count(app, "--threads", o.threads, 0, 4096, "worker threads (0: all)");
  add_count(app, "--every", o.every, 1, 100'000'000, "steps between samples of the share asleep");
  app.add_option("--out", o.out_dir, "folder for asleep-N.csv, sleep.gp and asleep_share.svg")->type_name("DIR");
  app.add_flag("--no-plot", o.no_plot, "write the CSV files but do not run gnuplot");
  add_count(app, "--drop-spheres", o.drop_spheres, 0, 10'000'000, "part 2's pile (0: skip part 2)");
  add_count(app, "--settle-steps", o.settle_steps, 1, 100'000'000, "most steps the pile may take to fall asleep");
  add_count(app, "--drop-steps", o.drop_steps, 1, 100'000'000, "steps after the drop");
}

int sleep_command(const std::vector<std::string>& args) {
  const std::optional<SleepOptions> parsed = parse_command("sleep", add_sleep_options, args);
  return parsed ? sleep_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
