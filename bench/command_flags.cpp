// Every hail-bench command's flags, in one file. CLI11 2.1 (Debian 12's libcli11-dev) is header
// only, and its header alone costs about 10 s of CPU per file that includes it in Release (GCC 12,
// -O2) and 44 s under ASan + UBSan: with each command declaring its flags in its own file, twelve
// files paid it, most of the ASan stage's build. Here the flags are declared once; the commands
// themselves (bench/<name>_command.cpp) see only their Options structs. The rules every flag
// follows are bench/cli.h's.

#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "accuracy_command.h"
#include "cli.h"
#include "compare_command.h"
#include "kernel/bvh/flat_node.h"
#include "pairs_command.h"
#include "query_command.h"
#include "rays_command.h"
#include "run_command.h"
#include "scale_command.h"
#include "scenes/stress_cases.h"
#include "sleep_command.h"
#include "solver_options.h"
#include "stress_command.h"

namespace hail::bench {
namespace {

[[noreturn]] void usage_error(const std::string& message) { throw std::invalid_argument(message); }

/// The sphere-pair searches by their names on the command line.
const std::map<std::string, PairSearch>& pair_search_names() {
  static const std::map<std::string, PairSearch> names{{"auto", PairSearch::Automatic},
                                                       {"brute", PairSearch::BruteForce},
                                                       {"grid", PairSearch::Grid},
                                                       {"sweep", PairSearch::SweepAndPrune},
                                                       {"bvh", PairSearch::Bvh}};
  return names;
}

}  // namespace

// `hail-bench run`

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
  add_count(app, "--reorder", p.reorder_interval, 0, 1'000'000'000, "steps between Morton re-sorts (0: never)");
  add_count(app, "--resting", p.resting_iterations, 0, kMaxIterations, "resting-contact passes per step");
  add_solver_options(app, p.solver, p.soft_step);
  app.add_option_function<std::string>(
         "--integrator",
         [&p](const std::string& v) {
           p.integrator = v == "uniform-acceleration" ? Integrator::UniformAcceleration : Integrator::SemiImplicitEuler;
         },
         "how positions follow velocities (WorldSettings::integrator)")
      ->check(CLI::IsMember({"semi-implicit-euler", "uniform-acceleration"}));
  add_count(app, "--tile", p.solver_tile_spheres, 0, 100'000'000,
            "spheres per solver tile: 0 (no tiles) or at least " + std::to_string(kMinSolverTileSpheres))
      ->check(CLI::Validator(
          [](std::string& v) {
            const long long n = std::stoll(v);  // whole_number_in ran first
            return n != 0 && n < static_cast<long long>(kMinSolverTileSpheres)
                       ? "must be 0 (no solver tiles) or a whole number in [" + std::to_string(kMinSolverTileSpheres) +
                             ", 100000000], got '" + v + "'"
                       : std::string();
          },
          ""));
  app.add_option_function<std::string>(
         "--warm-start",
         [&p](const std::string& v) {
           if (v == "on" || v == "off")
             p.warm_start = v == "on";
           else
             p.warm_start_factor = static_cast<float>(std::stod(v));
         },
         "warm starting; a factor in [0, 1] turns it on with that factor")
      ->check(CLI::Validator(
          [](std::string& v) {
            std::string factor = v;
            return v == "on" || v == "off" || number_in(0.0, 1.0)(factor).empty()
                       ? std::string()
                       : "must be on, off or a factor in [0, 1], got '" + v + "'";
          },
          "on|off|FACTOR"))
      ->type_name("on|off|FACTOR");
  app.add_option_function<std::string>(
         "--pairs", [&p](const std::string& v) { p.pair_search = pair_search_names().at(v); }, "the sphere-pair search")
      ->check(CLI::IsMember({"auto", "brute", "grid", "sweep", "bvh"}));
  app.add_option_function<std::string>(
         "--ccd",
         [&](const std::string& v) {
           p.continuous_collision = v != "off";
           o.ccd_both = v == "both";
         },
         "continuous collision; both: alternate runs with it on and off, one table")
      ->check(CLI::IsMember({"on", "off", "both"}));
  app.add_option_function<std::string>(
         "--rotation", [&p](const std::string& v) { p.rotation = v == "on"; },
         "off: spheres never spin (WorldSettings::rotation)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option_function<std::string>(
         "--sleep", [&p](const std::string& v) { p.sleep = v == "on"; },
         "on: islands at rest sleep and cost nothing until woken (WorldSettings::sleep)")
      ->check(CLI::IsMember({"on", "off"}));
  add_number(app, "--origin", o.origin, -1e7, 1e7,
             "m; run the scene moved by (D, 0, D) (World::shift_origin), to measure precision far from the origin");
  add_count(app, "--home-after", o.home_after, 1, 100'000'000,
            "with --origin D: after step K, World::shift_origin brings the scene back home (its error stays)");
  add_count(app, "--repeat", o.repeat, 1, 1000, "runs (default 0: 1; 3 with --ccd both or --filters compare)");
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
  app.add_flag("--quiet", o.quiet,
               "one summary line (scene, spheres, steps, ms/step, worst penetration, tunnelled, NaN, hash) and no "
               "progress lines on stderr; with --ccd both, the table");
  // The checks between flags, once every flag is read.
  app.callback([&app, &o] {
    if (o.home_after > 0 && o.origin == 0.0)
      usage_error("--home-after K needs --origin D (a scene moved out to bring home)");
    // The solver's flags too (they were left out, and --solver passes with --scene ran the file's solver).
    for (const char* flag : {"--spheres", "--threads", "--steps", "--dt", "--reorder", "--resting", "--tile", "--pairs",
                             "--ccd", "--rotation", "--warm-start", "--sleep", "--solver", "--substeps",
                             "--contact-cycles", "--damping-ratio", "--relax", "--integrator"})
      if (app.count(flag) > 0) o.given.emplace_back(flag);
    o.scene_named = app.count("scene") > 0;
    if (o.dump_every > 0 && o.dump_state_path.empty())
      usage_error("--dump-every " + std::to_string(o.dump_every) +
                  " needs --dump-state FILE.csv (the files are named after it)");
    if (o.ccd_both && (o.save_at > 0 || !o.restore_path.empty() || !o.expect_hash.empty() || !o.record_path.empty()))
      usage_error("--save-at, --restore, --expect-hash and --record take one world: not with --ccd both");
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
      for (const char* flag :
           {"--reorder", "--resting", "--tile", "--pairs", "--ccd", "--rotation", "--warm-start", "--sleep", "--solver",
            "--substeps", "--contact-cycles", "--damping-ratio", "--relax", "--depenetration-max", "--integrator"})
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

// `hail-bench accuracy`

void add_accuracy_options(CLI::App& app, AccuracyOptions& o) {
  app.description("error against wall time: known-answer cases and two scenes, for hail's knobs and the peers");
  app.add_option_function<std::string>(
         "--dt",
         [&o](const std::string& list) {
           o.dts.clear();
           for (std::size_t start = 0; start <= list.size();) {
             const std::size_t end = std::min(list.find(',', start), list.size());
             const std::string item = list.substr(start, end - start);
             o.dts.push_back(item.rfind("1/", 0) == 0 ? 1.0 / parse_real("--dt 1/N", item.substr(2), 1.0, 1e9)
                                                      : parse_real("--dt", item, 0.0, 1.0, /*exclude_min=*/true));
             start = end + 1;
           }
         },
         "time steps, comma-separated, each a number or 1/N in (0, 1] (default 1/60,1/240,1/1000)")
      ->type_name("LIST");
  add_count(app, "--spheres", o.scene_spheres, 1, 10'000'000, "spheres of the terrain-rain and bowl-pile cases");
  add_count(app, "--repeats", o.repeats, 1, 1000, "runs of each case; the median wall time is reported");
  app.add_option("--out", o.out_dir, "folder of the CSV, JSON and plots")->type_name("DIR");
  app.add_flag("--no-plot", o.no_plot, "no gnuplot SVGs");
  app.add_flag("--no-scenes", o.no_scenes, "the known-answer cases only");
  app.add_flag("--quiet", o.quiet, "no progress lines on stderr");
  add_soft_step_options(app, o.soft);
  app.add_option("--variants", o.only, "only these engines / knobs (as the table names them), comma-separated")
      ->delimiter(',')
      ->type_name("LIST");
}

int accuracy_command(const std::vector<std::string>& args) {
  const std::optional<AccuracyOptions> parsed = parse_command("accuracy", add_accuracy_options, args);
  return parsed ? accuracy_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench compare`

void add_compare_options(CLI::App& app, CompareOptions& o) {
  app.description("hail and Bullet (if built in) on the identical scene, R runs each alternating ABBA: one table");
  app.add_option("scene", o.scene, "a built-in scene")->check(CLI::IsMember(scene_names()));
  add_count(app, "--spheres", o.params.spheres, 1, 10'000'000, "sphere count");
  add_count(app, "--threads", o.params.threads, 0, 4096, "hail's worker threads (0: all; Bullet runs on one)");
  add_count(app, "--steps", o.steps, 1, 100'000'000, "steps (default -1: the scene's)");
  add_count(app, "--repeat", o.repeat, 1, 1000, "runs of each engine");
  app.add_option("--json", o.json_path, "every figure as JSON")->type_name("FILE");
  app.add_flag("--quiet", o.quiet, "no progress lines on stderr");
}

int compare_command(const std::vector<std::string>& args) {
  const std::optional<CompareOptions> parsed = parse_command("compare", add_compare_options, args);
  return parsed ? compare_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench stress`

void add_stress_options(CLI::App& app, StressOptions& o) {
  std::vector<std::string> names;
  for (const StressCase& c : stress_cases()) names.push_back(c.name);
  app.description("the stability battery: each stiff or extreme case with its invariants; exit status 1 if any fails");
  // A misspelt case name is refused before the header, naming the cases there are.
  app.add_option("--case", o.only, "run this case alone")->check(CLI::IsMember(names))->type_name("NAME");
  app.add_flag("--quick", o.quick, "skip the slow cases");
  app.add_option_function<std::string>(
         "--solver", [&o](const std::string& v) { o.solver = v == "soft" ? Solver::SoftStep : Solver::Passes; },
         "the contact solver every case runs: passes (the default) or soft (the soft step)")
      ->check(CLI::IsMember({"passes", "soft"}));
  app.add_option("--json", o.json_path, "every case's worst values as JSON")->type_name("FILE");
}

int stress_command(const std::vector<std::string>& args) {
  const std::optional<StressOptions> parsed = parse_command("stress", add_stress_options, args);
  return parsed ? stress_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench scale`

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

// `hail-bench query and bvh-build`

void add_query_options(CLI::App& app, QueryOptions& o) {
  app.description("terrain query microbenchmark: BVH walks (stackless, fixed stack, packet), grid lookup, brute force");
  add_count(app, "--queries", o.queries, 1, 100'000'000, "spheres queried");
  add_count(app, "--leaf", o.leaf, 1, kMaxLeafSize, "triangles per BVH leaf (default the terrain's)");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
}

int query_command(const std::vector<std::string>& args) {
  const std::optional<QueryOptions> parsed = parse_command("query", add_query_options, args);
  return parsed ? query_command(*parsed) : 0;  // 0 after --help
}

void add_bvh_build_options(CLI::App& app, BvhBuildCommandOptions& o) {
  app.description("BVH build time (median split and binned SAH) for 256^2, 1024^2 (and 4096^2) heightmaps");
  add_count(app, "--max-side", o.max_side, 1, 65536, "the largest heightmap side built (4096 takes about 2 GB)");
}

int bvh_build_command(const std::vector<std::string>& args) {
  const std::optional<BvhBuildCommandOptions> parsed = parse_command("bvh-build", add_bvh_build_options, args);
  return parsed ? bvh_build_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench pairs`

void add_pairs_options(CLI::App& app, PairsOptions& o) {
  app.description("sphere-sphere pair searches (brute force, grid, sweep and prune, sphere BVH) by N and radius mix");
  add_count(app, "--max", o.max_n, 1, 10'000'000, "the largest sphere count");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
}

int pairs_command(const std::vector<std::string>& args) {
  const std::optional<PairsOptions> parsed = parse_command("pairs", add_pairs_options, args);
  return parsed ? pairs_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench rays`

void add_rays_options(CLI::App& app, RaysOptions& o) {
  app.description("World::raycast_batch throughput (rays/s) against a brute-force loop, by sphere count");
  app.add_option("--sizes", o.sizes, "sphere counts, comma-separated (e.g. 1000,16000,64000,256000,1000000)");
  add_count(app, "--rays", o.rays, 1, 100'000'000, "rays per batch");
  add_count(app, "--threads", o.threads, 1, 1024, "threads of the World's arena");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
  add_count(app, "--brute-budget", o.brute_budget, 1, 1'000'000'000'000LL,
            "ray-sphere tests the brute force may make per repeat (its rays are cut to fit, at least 64)");
}

int rays_command(const std::vector<std::string>& args) {
  const std::optional<RaysOptions> parsed = parse_command("rays", add_rays_options, args);
  return parsed ? rays_command(*parsed) : 0;  // 0 after --help
}

// `hail-bench sleep`

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

// The solver's flags (run, and the soft step's knobs in accuracy); bench/solver_options.h

void add_solver_options(CLI::App& app, Solver& solver, SoftStepParams& soft) {
  app.add_option_function<std::string>(
         "--solver", [&solver](const std::string& v) { solver = v == "soft" ? Solver::SoftStep : Solver::Passes; },
         "the contact solver: passes (collision and resting passes, the default) or soft (Box2D v3's soft step)")
      ->check(CLI::IsMember({"passes", "soft"}));
  add_soft_step_options(app, soft);
}

void add_soft_step_options(CLI::App& app, SoftStepParams& soft) {
  add_count(app, "--substeps", soft.substeps, 1, kMaxIterations, "soft step: substeps per step");
  add_number(app, "--contact-cycles", soft.contact_cycles, 0.0, 0.25,
             "soft step: contact stiffness, cycles per substep (ground contacts twice this)", /*exclude_min=*/true);
  add_number(app, "--damping-ratio", soft.damping_ratio, 0.0, 1e6, "soft step: contact damping ratio",
             /*exclude_min=*/true);
  add_count(app, "--relax", soft.relax_iterations, 0, kMaxIterations, "soft step: relax iterations per substep");
  add_count(app, "--depenetration-max", soft.depenetration_iterations_max, 0, kMaxIterations,
            "soft step: most depenetration passes a step (past depenetration_iterations while an overlap is "
            "beyond twice the slop)");
}

}  // namespace hail::bench
