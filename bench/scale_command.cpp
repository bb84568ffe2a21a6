#include "scale_command.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <thread>

#include "cli.h"
#include "gnuplot.h"
#include "scenes/machine_info.h"
#include "scenes/memory_use.h"
#include "scenes/output_file.h"
#include "scenes/scene_run.h"

namespace hail::bench {
namespace {

/// A count is run only if the largest bytes per sphere seen so far, times this, times the count
/// (plus the terrain) fits the memory limit: deeper piles hold more contacts per sphere.
constexpr double kMemoryHeadroom = 1.5;

}  // namespace

namespace {

// Reads the two matrices written beside scale.csv (gnuplot joins points only within one column).
const char* kGnuplotScript = R"(# hail-bench scale: ns per sphere-step against spheres, and speed-up against threads.
set terminal svg size 900,420 dynamic font 'sans,11'
set key top left
set grid
set output 'ns_per_sphere_step.svg'
set logscale x 2
set xlabel 'spheres'
set ylabel 'ns per sphere-step (mean over timed steps)'
set title TITLE
plot for [t=1:THREADS] 'ns_per_sphere_step.dat' using 1:(column(t + 1)) with linespoints title sprintf('%d thread%s', t, t > 1 ? 's' : '')
set output 'speedup.svg'
unset logscale x
set xlabel 'threads'
set ylabel 'speed-up over 1 thread'
set xtics 1
plot for [k=1:COUNTS] 'speedup.dat' using 1:(column(k + 1)) with linespoints title columnheader(k + 1), x with lines dashtype 2 title 'ideal'
)";

}  // namespace

int scale_command(const ScaleOptions& o) {
  const SceneEntry& entry = find_scene(o.scene);
  prepare_output_dir(o.out_dir);  // before the runs: a folder that cannot be written fails now, not at the end
  std::vector<std::size_t> counts;
  for (std::size_t n = o.min_spheres; n <= o.max_spheres; n *= 2) counts.push_back(n);

  std::printf("hail-bench scale %s: %zu..%zu spheres (doubling), 1..%d threads, %d steps each (timed from step %d)\n",
              o.scene.c_str(), o.min_spheres, o.max_spheres, o.max_threads, o.steps, o.steps > 120 ? 60 : 0);
  std::printf("  machine %s, SIMD %s; output in %s/\n", cpu_model().c_str(), simd_path().c_str(), o.out_dir.c_str());
  // The memory limit: a count whose estimate (measured bytes per sphere so far) is over it is
  // not started, so that a --max beyond the machine ends with a message and every row so far
  // written, not with the kernel's OOM kill.
  const double limit_bytes = memory_limit_bytes(o.memory_limit_gb);
  std::printf("  memory limit %s", describe_memory_limit(o.memory_limit_gb, limit_bytes).c_str());
  if (limit_bytes > 0.0)
    std::printf("; each count must fit it at %.1fx the largest bytes per sphere so far", kMemoryHeadroom);
  std::printf("\n");
  std::printf("  %9s %3s %10s %10s %8s %8s | %7s %7s %7s %7s %7s %7s %7s | %9s %9s %6s %7s %4s %s\n", "spheres", "thr",
              "ms/step", "ns/sph-st", "median", "speedup", "reorder", "terrain", "pairs", "solve", "sweep", "integr",
              "depen", "pen.sph", "pen.grnd", "tunnel", "felloff", "NaN", "hash, heap at the end (bytes per sphere)");

  // Written row by row (flushed and checked after each, so that a full disk stops the runs
  // early) into a temporary that replaces scale.csv when every row is in.
  AtomicOutputFile csv_file(o.out_dir + "/scale.csv");
  std::ostream& csv = csv_file.stream();
  csv << "spheres,threads,ms_per_step_mean,ms_per_step_median,ns_per_sphere_step,speedup,reorder_ms,predict_ms,"
         "detect_terrain_ms,detect_pairs_ms,solve_ms,sweep_ms,integrate_ms,depenetrate_ms,max_sphere_penetration,"
         "max_terrain_penetration,tunnelled,fell_off,nan_count,kinetic_energy,state_hash,heap_at_end_bytes,bytes_per_"
         "sphere,"
         "mean_step_sphere_penetration,mean_step_static_penetration\n";
  nlohmann::json runs = nlohmann::json::array();
  std::vector<std::vector<double>> ns_table(counts.size()), speedup_table(counts.size());  // [count][thread - 1]
  bool deterministic = true, finite = true;
  double most_bytes_per_sphere = 0.0, terrain_bytes = 0.0;
  std::size_t counts_run = 0;
  for (const std::size_t& n : counts) {
    const double estimate = terrain_bytes + kMemoryHeadroom * most_bytes_per_sphere * double(n);
    if (limit_bytes > 0.0 && estimate > limit_bytes) {
      char why[256];
      std::snprintf(
          why, sizeof why,
          "stopping before %zu spheres: about %s estimated (%.0f bytes per sphere measured so far, x%.1f), over "
          "the memory limit of %s (--memory-limit GB; 0: none)",
          n, format_bytes(estimate).c_str(), most_bytes_per_sphere, kMemoryHeadroom, format_bytes(limit_bytes).c_str());
      std::printf("  %s\n", why);
      std::fprintf(stderr, "hail-bench scale: %s\n", why);
      break;
    }
    ++counts_run;
    double one_thread_ms = 0.0;
    std::string one_thread_hash;
    for (int t = 1; t <= o.max_threads; ++t) {
      SceneParams params;
      params.spheres = n;
      params.threads = t;
      RunOptions run_options;
      run_options.steps = o.steps;
      run_options.progress_label = std::to_string(n) + " spheres, " + std::to_string(t) + " threads: ";
      const RunResult r = run_scene(entry, params, run_options);
      most_bytes_per_sphere = std::max(most_bytes_per_sphere, r.bytes_per_sphere());
      terrain_bytes = double(r.terrain_bytes);
      if (t == 1) one_thread_ms = r.mean_ms, one_thread_hash = r.state_hash;
      deterministic = deterministic && r.state_hash == one_thread_hash;
      finite = finite && r.errors.nan_count == 0;
      const double ns = 1e6 * r.mean_ms / double(r.spheres);
      const double speedup = one_thread_ms / r.mean_ms;
      const PhaseTimes& p = r.phase_ms;
      const ErrorFigures& e = r.errors;
      std::printf(
          "  %9zu %3d %10.3f %10.1f %8.3f %8.2f | %7.2f %7.2f %7.2f %7.2f %7.2f %7.2f %7.2f | %9.4f %9.4f %6zu %7zu "
          "%4zu %s %s (%.0f)\n",
          r.spheres, t, r.mean_ms, ns, r.median_ms, speedup, p.reorder, p.detect_terrain, p.detect_pairs, p.solve,
          p.sweep, p.integrate, p.depenetrate, e.max_sphere_penetration, e.max_terrain_penetration, e.tunnelled,
          e.fell_off, e.nan_count, r.state_hash.c_str(),
          r.heap_measured ? format_bytes(double(r.heap_at_end)).c_str() : "n/a", r.bytes_per_sphere());
      std::fflush(stdout);
      csv << r.spheres << ',' << t << ',' << r.mean_ms << ',' << r.median_ms << ',' << ns << ',' << speedup << ','
          << p.reorder << ',' << p.predict << ',' << p.detect_terrain << ',' << p.detect_pairs << ',' << p.solve << ','
          << p.sweep << ',' << p.integrate << ',' << p.depenetrate << ',' << e.max_sphere_penetration << ','
          << e.max_terrain_penetration << ',' << e.tunnelled << ',' << e.fell_off << ',' << e.nan_count << ','
          << e.kinetic_energy << ',' << r.state_hash << ',' << r.heap_at_end << ',' << r.bytes_per_sphere() << ','
          << e.mean_step_sphere_penetration << ',' << e.mean_step_static_penetration << '\n';
      csv_file.flush();
      const std::size_t row = static_cast<std::size_t>(&n - counts.data());
      ns_table[row].push_back(ns);
      speedup_table[row].push_back(speedup);
      nlohmann::json j = to_json(r);
      j["speedup"] = speedup;
      runs.push_back(j);
    }
  }
  counts.resize(counts_run);  // the counts the memory limit left out have no rows
  csv_file.commit();
  write_file_atomically(o.out_dir + "/scale.json", [&](std::ostream& out) {
    out << nlohmann::json{{"scene", o.scene}, {"memory_limit_bytes", limit_bytes}, {"runs", runs}}.dump(2) << "\n";
  });
  std::printf("  same state hash on every thread count: %s; NaN-free: %s\n", deterministic ? "yes" : "NO",
              finite ? "yes" : "NO");

  if (!o.no_plot) {
    write_file_atomically(o.out_dir + "/scale.gp", [](std::ostream& gp) { gp << kGnuplotScript; });
    write_file_atomically(o.out_dir + "/ns_per_sphere_step.dat", [&](std::ostream& ns_dat) {
      ns_dat << "# spheres, then ns per sphere-step for 1.." << o.max_threads << " threads\n";
      for (std::size_t c = 0; c < counts.size(); ++c) {
        ns_dat << counts[c];
        for (double v : ns_table[c]) ns_dat << ' ' << v;
        ns_dat << '\n';
      }
    });
    write_file_atomically(o.out_dir + "/speedup.dat", [&](std::ostream& speedup_dat) {
      speedup_dat << "threads";
      for (std::size_t n : counts) speedup_dat << " \"" << n << " spheres\"";
      speedup_dat << '\n';
      for (int t = 1; t <= o.max_threads; ++t) {
        speedup_dat << t;
        for (std::size_t c = 0; c < counts.size(); ++c)
          speedup_dat << ' ' << speedup_table[c][static_cast<std::size_t>(t - 1)];
        speedup_dat << '\n';
      }
    });
    const std::string title = o.scene + " on " + cpu_model() + " (" + simd_path() + ")";
    plot_with_gnuplot(o.out_dir, "scale.gp",
                      "TITLE=" + gnuplot_string(title) + "; THREADS=" + std::to_string(o.max_threads) +
                          "; COUNTS=" + std::to_string(counts.size()),
                      o.out_dir + "/ns_per_sphere_step.svg, " + o.out_dir + "/speedup.svg");
  }
  return deterministic && finite ? 0 : 3;
}

// The flags of `hail-bench scale` (bench/cli.h's rules).

void add_scale_options(CLI::App& app, ScaleOptions& o) {
  constexpr long long kMax = static_cast<long long>(kScaleMaxSpheres);
  app.description("the scene at doubling sphere counts on 1..T threads: table, CSV, JSON and gnuplot SVGs");
  app.add_option("scene", o.scene, "a built-in scene")->check(CLI::IsMember(scene_names()));
  add_count(app, "--min", o.min_spheres, 1, kMax, "the smallest sphere count");
  add_count(app, "--max", o.max_spheres, 1, kMax, "the largest sphere count");
  add_count(app, "--threads", o.max_threads, 0, 4096, "the most threads (0: the hardware's)");
  add_count(app, "--steps", o.steps, 1, 100'000'000, "steps of each run");
  app.add_option("--out", o.out_dir, "folder of the CSV, JSON and plots")->type_name("DIR");
  add_number(app, "--memory-limit", o.memory_limit_gb, 0.0, 1e9,
             "GB; a count whose estimate exceeds it is not started (default -1: 80% of the memory available; 0: none)");
  app.add_flag("--no-plot", o.no_plot, "no gnuplot SVGs");
  app.callback([&o] {
    if (o.min_spheres > o.max_spheres)
      throw std::invalid_argument("--min (" + std::to_string(o.min_spheres) + ") must not exceed --max (" +
                                  std::to_string(o.max_spheres) + ")");
    if (o.max_threads == 0) o.max_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  });
}

int scale_command(const std::vector<std::string>& args) {
  const std::optional<ScaleOptions> parsed = parse_command("scale", add_scale_options, args);
  return parsed ? scale_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
