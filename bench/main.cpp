// hail-bench: the benchmark tool. Every time it prints comes with the run's error figures,
// the machine, the SIMD path and a hash of the final state.

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "accuracy_command.h"
#include "compare_command.h"
#include "hail/errors.h"
#include "kernel/dispatch/simd_dispatch.h"
#include "pairs_command.h"
#include "query_command.h"
#include "run_command.h"
#include "scale_command.h"
#include "stress_command.h"
#include "bench/scenes/scenes.h"

namespace {

void print_help() {
  std::puts(
      "usage: hail-bench <command> [options] [--simd sse4.2|avx2|avx512]\n"
      "\n"
      "  --simd PATH  (any command) run the SIMD kernels of PATH instead of the widest this CPU supports;\n"
      "               overrides the HAIL_SIMD environment variable; a path this CPU lacks is an error\n"
      "  hail-bench <command> --help  lists that command's options with the range each accepts\n"
      "  exit status: 2 for a bad command line (an unknown option, a count not a whole number in range,\n"
      "               an output that cannot be written or would overwrite an input), 1 if a run or a write\n"
      "               failed, 3 if a run ended with NaN (stress: 1 if a case failed)\n"
      "\n"
      "commands:\n"
      "  run <scene> [--spheres N] [--steps S] [--threads T] [--dt DT] [--reorder K] [--pairs auto|brute|grid|sweep|bvh] [--warm-start on|off|FACTOR] [--resting N] [--tile N] [--ccd on|off|both] [--rotation on|off] [--repeat R] [--json FILE] [--trace FILE] [--dump-state FILE.csv [--dump-every K]] [--memory-limit GB] [--quiet]\n"
      "      step a scene; print ms/step (mean, median), per-phase split and error figures\n"
      "      (penetration, tunnelled, fell off, NaN, energy and momentum drift, state hash);\n"
      "      --trace writes a Chrome trace-event JSON (Perfetto): one slice per phase per step per thread;\n"
      "      --ccd both runs continuous collision on and off R times each (default 3), alternating ABBA,\n"
      "      and prints one table with the ratio of the medians; --repeat R alone repeats the run;\n"
      "      --rotation off: spheres never spin (friction on linear velocities only; WorldSettings::rotation);\n"
      "      a sphere count that could not fit the memory limit (2.1 kB a sphere; default 80% of the memory\n"
      "      available, --memory-limit GB, 0: none) is refused before anything is built\n"
      "  run --scene FILE.json [same options] [--dump-state FILE.csv]\n"
      "      run a scene described in a JSON file (docs/scene_format.md; data/scenes/ has the built-in ones);\n"
      "      options given override the file's values; --dump-state writes id,x,y,z,vx,vy,vz,wx,wy,wz per sphere\n"
      "  accuracy [--dt 1/60,1/240,1/1000] [--spheres N] [--repeats R] [--out DIR] [--no-scenes] [--no-plot]\n"
      "      error against wall time: the known-answer cases (bounce, slide-to-roll, head-on, cradle, slope roll)\n"
      "      for hail's knobs (integrator, substeps, solver passes) and the peers found at build time, at each dt;\n"
      "      terrain-rain and bowl-pile (N spheres) against a dt/16 reference; table, CSV, JSON, gnuplot SVGs\n"
      "  compare <scene> [--spheres N] [--threads T] [--steps S] [--repeat R] [--json FILE] [--quiet]\n"
      "      hail and Bullet (libbullet-dev, if found at configure time; single-threaded) on the identical scene,\n"
      "      R runs each (default 3) alternating ABBA, Bullet with sleeping on (its default) and off: one table of\n"
      "      ms/step (median, mean, ratio) and error figures side by side; without Bullet, hail alone\n"
      "  stress [--case NAME] [--quick] [--json FILE]\n"
      "      the stability battery: each stiff or extreme case with its invariants and the worst values\n"
      "      measured over every step; exit status 1 if any case fails (--quick skips the slow ones)\n"
      "  scale [scene] [--min N] [--max N] [--threads T] [--steps S] [--out DIR] [--memory-limit GB] [--no-plot]\n"
      "      the scene at doubling sphere counts (default 1000..256000) on 1..T threads (default: all):\n"
      "      table, DIR/scale.csv, DIR/scale.json, and gnuplot SVGs of ns per sphere-step and speed-up;\n"
      "      with the heap each run holds; a count whose estimate (1.5x the bytes per sphere measured so far)\n"
      "      exceeds the memory limit (default 80% of the memory available; 0: none) is not started\n"
      "  query [--queries N] [--leaf L (default 8, the terrain's)] [--repeats R]\n"
      "      terrain query microbenchmark, random and Morton order: stackless and fixed-stack BVH walks,\n"
      "      packet walk (4, 8 or 16 spheres per node test by SIMD path, with and without SIMD leaf boxes), grid-cell lookup,\n"
      "      brute force\n"
      "  pairs [--max N] [--repeats R]\n"
      "      sphere-sphere pair searches (brute force, grid, sweep and prune, sphere BVH) by N and radius mix\n"
      "  bvh-build [--max-side 4096]\n"
      "      BVH build time (median split and binned SAH) for 256^2, 1024^2 (and 4096^2) heightmaps\n"
      "\n"
      "scenes (defined exactly in docs/scenes.md):");
  for (const auto& s : hail::bench::scene_registry()) std::printf("  %-14s %s\n", s.name, s.summary);
}

/// Takes `--simd PATH` out of the arguments (before or after the command) and makes PATH the
/// active SIMD path; hail::InvalidArgument if it is unknown or this CPU lacks it.
void apply_simd_option(std::vector<std::string>& args) {
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (args[k] != "--simd") continue;
    if (k + 1 >= args.size()) throw hail::InvalidArgument("--simd needs a value: sse4.2, avx2 or avx512");
    hail::set_simd_path(hail::parse_simd_path(args[k + 1]));
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(k), args.begin() + static_cast<std::ptrdiff_t>(k) + 2);
    --k;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    print_help();
    return args.empty() ? 2 : 0;
  }
  try {
    apply_simd_option(args);
    if (args.empty()) {
      print_help();
      return 2;
    }
    // Resolves HAIL_SIMD now (when --simd did not choose), so that a bad value stops the run
    // before it starts, with the message of hail::InvalidArgument.
    (void)hail::active_simd_path();
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (args[0] == "run") return hail::bench::run_command(rest);
    if (args[0] == "accuracy") return hail::bench::accuracy_command(rest);
    if (args[0] == "stress") return hail::bench::stress_command(rest);
    if (args[0] == "compare") return hail::bench::compare_command(rest);
    if (args[0] == "scale") return hail::bench::scale_command(rest);
    if (args[0] == "pairs") return hail::bench::pairs_command(rest);
    if (args[0] == "query") return hail::bench::query_command(rest);
    if (args[0] == "bvh-build") return hail::bench::bvh_build_command(rest);
    std::fprintf(stderr, "hail-bench: unknown command '%s' (try --help)\n", args[0].c_str());
    return 2;
  } catch (const std::invalid_argument& e) {  // hail::InvalidArgument too: a bad command line or input
    std::fprintf(stderr, "hail-bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // a run or a write that failed
    std::fprintf(stderr, "hail-bench: %s\n", e.what());
    return 1;
  }
}
