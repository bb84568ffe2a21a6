// hail-bench's command line (CLI11, with the shared validators of bench/cli.h) and every
// command's use of it: counts are whole numbers in range, unknown flags are errors naming the
// flag, --help for hail-bench and each command; hail-bench run's --quiet line and --dump-every.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/accuracy_command.h"
#include "bench/bvh_build_command.h"
#include "bench/cli.h"
#include "bench/command_line.h"
#include "bench/compare_command.h"
#include "bench/pairs_command.h"
#include "bench/query_command.h"
#include "bench/rays_command.h"
#include "bench/run_command.h"
#include "bench/scale_command.h"
#include "bench/sleep_command.h"
#include "bench/stress_command.h"
#include "tests/catch.h"

namespace bench = hail::bench;
using Command = int (*)(const std::vector<std::string>&);

namespace {

/// The message of the std::invalid_argument `command(args)` throws, or "(no error)".
std::string refusal(Command command, const std::vector<std::string>& args) {
  try {
    command(args);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// An empty folder of that name under the temporary folder.
std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("A count must be a whole number in its range; the message names the flag, the range and the text",
          "[bench][cli]") {
  CHECK(bench::parse_count("--steps", "600", 1, 1000) == 600);
  CHECK(bench::parse_count("--spheres", "1e6", 1, 100'000'000) == 1'000'000);  // exponent form, a whole number
  CHECK(bench::parse_count("--threads", "0", 0, 64) == 0);
  auto message = [](const std::string& text) {
    try {
      (void)bench::parse_count("--steps", text, 1, 100'000'000);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  // 1e10 once overflowed an int and came out as "must be >= 1"; 2.7 was truncated to 2.
  CHECK(message("1e10") == "--steps: must be a whole number in [1, 100000000], got '1e10'");
  CHECK(message("2.7") == "--steps: must be a whole number in [1, 100000000], got '2.7'");
  for (const char* bad : {"0", "-3", "", " 5", "5x", "abc", "inf", "nan", "0.5"}) {
    INFO(bad);
    CHECK(contains(message(bad), "[1, 100000000], got '" + std::string(bad) + "'"));
  }
  CHECK(bench::parse_real("--dt", "0.01", 0.0, 10.0, true) == 0.01);
  CHECK_THROWS_AS(bench::parse_real("--dt", "0", 0.0, 10.0, true), std::invalid_argument);
  CHECK_THROWS_WITH(bench::parse_real("--dt", "11", 0.0, 10.0, true), "--dt: must be a number in (0, 10], got '11'");
}

namespace {

/// A command of a few flags, parsed as every hail-bench command is.
struct DemoOptions {
  int steps = 7;
  double dt = 0.5;
  bool quiet = false;
  std::string scene = "default", json;
};

void add_demo_options(CLI::App& app, DemoOptions& o) {
  app.add_option("scene", o.scene, "the scene");
  bench::add_count(app, "--steps", o.steps, 1, 1000, "steps");
  bench::add_number(app, "--dt", o.dt, 0.0, 1.0, "time step", /*exclude_min=*/true);
  app.add_flag("--quiet", o.quiet, "quiet");
  app.add_option("--json", o.json, "output");
}

/// The message of the std::invalid_argument parsing `args` as the demo command throws, or "(no error)".
std::string demo_error(const std::vector<std::string>& args) {
  try {
    (void)bench::parse_command("demo", add_demo_options, args);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE(
    "The shared conventions: unknown flags, missing values, --flag=value, a positional, the last flag wins, --help",
    "[bench][cli]") {
  const std::optional<DemoOptions> o = bench::parse_command(
      "demo", add_demo_options, {"rain", "--steps=12", "--quiet", "--json", "x.json", "--dt", "0.1", "--dt", "0.25"});
  REQUIRE(o);
  CHECK(o->scene == "rain");
  CHECK(o->steps == 12);
  CHECK(o->quiet);
  CHECK(o->json == "x.json");
  CHECK(o->dt == 0.25);  // the last of a repeated flag wins, as before CLI11
  CHECK(bench::parse_command("demo", add_demo_options, {"--steps", "1e3"})->steps == 1000);
  CHECK(demo_error({"--stpes", "3"}) ==
        "The following argument was not expected: --stpes (see hail-bench demo --help)");
  CHECK(contains(demo_error({"--steps"}), "--steps"));
  CHECK(contains(demo_error({"--steps", "2.7"}), "--steps: must be a whole number in [1, 1000], got '2.7'"));
  CHECK(contains(demo_error({"--dt", "0"}), "--dt: must be a number in (0, 1], got '0'"));
  CHECK(contains(demo_error({"--dt", "nan"}), "--dt: must be a number in (0, 1], got 'nan'"));
  CHECK(contains(demo_error({"a", "b"}), "not expected: b"));
  CHECK_FALSE(bench::parse_command("demo", add_demo_options,
                                   {"--steps", "9", "--help"}));  // --help: usage printed, nothing run
  CLI::App app("a test command", "hail-bench demo");
  DemoOptions options;
  add_demo_options(app, options);
  const std::string usage = app.help();
  CHECK(contains(usage, "hail-bench demo"));
  CHECK(contains(usage, "--steps N"));
  CHECK(contains(usage, "whole number in [1, 1000]"));
}

TEST_CASE("Every hail-bench command parses with CLI11: unknown flags and bad counts are refused", "[bench][cli]") {
  // query, pairs and bvh-build once ignored unknown flags and reported a bad number as "stoi".
  const std::pair<const char*, Command> commands[] = {
      {"run", bench::run_command},       {"accuracy", bench::accuracy_command},   {"compare", bench::compare_command},
      {"stress", bench::stress_command}, {"scale", bench::scale_command},         {"query", bench::query_command},
      {"pairs", bench::pairs_command},   {"bvh-build", bench::bvh_build_command}, {"rays", bench::rays_command},
      {"sleep", bench::sleep_command}};
  for (const auto& [name, command] : commands) {
    INFO(name);
    CHECK(refusal(command, {"--bogus-flag"}) ==
          "The following argument was not expected: --bogus-flag (see hail-bench " + std::string(name) + " --help)");
    CHECK(command({"--help"}) == 0);  // prints the command's usage and runs nothing
  }
  CHECK(refusal(bench::query_command, {"--queries", "many"}) ==
        "--queries: must be a whole number in [1, 100000000], got 'many' (see hail-bench query --help)");
  CHECK(contains(refusal(bench::query_command, {"--leaf", "9"}), "--leaf: must be a whole number in [1, 8], got '9'"));
  CHECK(contains(refusal(bench::pairs_command, {"--repeats", "2.5"}), "--repeats: must be a whole number"));
  CHECK(contains(refusal(bench::bvh_build_command, {"--max-side", "x"}), "--max-side: must be a whole number"));
  CHECK(refusal(bench::run_command, {"--steps", "1e10"}) ==
        "--steps: must be a whole number in [1, 100000000], got '1e10' (see hail-bench run --help)");
  CHECK(contains(refusal(bench::run_command, {"--steps", "2.7"}), "got '2.7'"));
  CHECK(contains(refusal(bench::run_command, {"--threads", "-1"}),
                 "--threads: must be a whole number in [0, 4096], got '-1'"));
  // The setting flags are made from the settings table: they take what --set takes and are
  // checked by World::validate's rules, naming the flag and the setting.
  CHECK(contains(refusal(bench::run_command, {"--pairs", "octree"}),
                 "--pairs: pair_search takes one of auto|brute|grid|sweep|bvh"));
  CHECK(contains(refusal(bench::run_command, {"--resting", "5000"}),
                 "--resting: resting_iterations takes a whole number in [0, 1000]"));
  CHECK(contains(refusal(bench::run_command, {"--contact-cycles", "0"}),
                 "--contact-cycles: soft_step.contact_cycles must be finite and in (0, 0.25]"));
  CHECK(contains(refusal(bench::accuracy_command, {"--relax", "x"}),
                 "--relax: soft_step.relax_iterations takes a whole number"));
  CHECK(contains(refusal(bench::stress_command, {"--solver", "stiff"}), "--solver: solver takes one of passes|soft"));
  CHECK(contains(refusal(bench::run_command, {"--tile", "3"}),
                 "--tile: solver_tile_spheres must be 0 (no tiles) or >= "));
  CHECK(contains(refusal(bench::scale_command, {"--min", "64", "--max", "8"}), "--min (64) must not exceed --max (8)"));
  CHECK(contains(refusal(bench::compare_command, {"--repeat", "0"}), "--repeat: must be a whole number in [1, 1000]"));
  CHECK(contains(refusal(bench::run_command, {"no-such-scene"}), "scene: no-such-scene not in {"));
  CHECK(contains(refusal(bench::run_command, {"--spheres", "0"}),
                 "--spheres: must be a whole number in [1, 100000000], got '0'"));
  CHECK(contains(refusal(bench::run_command, {"--ccd", "maybe"}), "--ccd: continuous_collision takes on, off"));
  CHECK(contains(refusal(bench::run_command, {"--ccd", "on", "--ccd-both"}), "--ccd-both runs with --ccd on and off"));
  CHECK(contains(refusal(bench::run_command, {"--dt", "0"}), "--dt: must be a number in (0, 10], got '0'"));
  // A misspelt stress case is refused naming the cases there are (it printed the table's header first).
  CHECK(contains(refusal(bench::stress_command, {"--case", "bowl-pile"}), "--case: bowl-pile not in {"));
  CHECK(contains(refusal(bench::stress_command, {"--case", "bowl-pile"}), "bowl-pile-10k-20s"));
  CHECK(contains(refusal(bench::stress_command, {"--case", "bowl-pile-10k-20s", "--quick"}), "is a slow case"));
}

TEST_CASE("hail-bench accuracy refuses a repeat count that rounds to 0 (it crashed in median())", "[bench][cli]") {
  CHECK(refusal(bench::accuracy_command, {"--repeats", "0.5"}) ==
        "--repeats: must be a whole number in [1, 1000], got '0.5' (see hail-bench accuracy --help)");
  CHECK(contains(refusal(bench::accuracy_command, {"--repeats", "0"}), "[1, 1000], got '0'"));
  CHECK(contains(refusal(bench::accuracy_command, {"--spheres", "0.5"}), "--spheres: must be a whole number"));
  CHECK(
      contains(refusal(bench::accuracy_command, {"--dt", "1/0"}), "--dt 1/N: must be a number in [1, 1e+09], got '0'"));
}

TEST_CASE("hail-bench run --scene FILE: flags given override the file's values, the others stand", "[bench][cli]") {
  const auto dir = fresh_dir("hail-test-cli-args-scene");
  const std::string scene = (dir / "scene.json").string(), json = (dir / "run.json").string();
  std::ofstream(scene) << R"({"format": "hail-scene", "version": 1, "dt": 0.01, "steps": 4,
    "spheres": [{"list": [{"position": [0, 1, 0], "radius": 0.5}, {"position": [2, 1, 0], "radius": 0.5}]}]})";
  auto run_json = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"--scene", scene, "--quiet", "--json", json};
    args.insert(args.end(), extra.begin(), extra.end());
    REQUIRE(bench::run_command(args) == 0);
    std::ifstream in(json);
    return nlohmann::json::parse(in);
  };
  const nlohmann::json from_file = run_json({});
  CHECK(from_file["steps"] == 4);
  CHECK(from_file["dt"].get<double>() == Approx(0.01));
  const nlohmann::json overridden = run_json({"--steps", "6"});
  CHECK(overridden["steps"] == 6);
  CHECK(overridden["dt"].get<double>() == Approx(0.01));
  // The solver's flags apply to a scene file too (--solver and the soft step's knobs were not
  // passed on): the spheres fall (the integrator moves them differently) and the second one
  // overlaps the third (the solvers part them differently).
  std::ofstream(scene) << R"({"format": "hail-scene", "version": 1, "dt": 0.01, "steps": 4,
    "spheres": [{"list": [{"position": [0, 1, 0], "radius": 0.5}, {"position": [2, 1, 0], "radius": 0.5},
                          {"position": [2.8, 1, 0], "radius": 0.5}]}]})";
  const nlohmann::json plain = run_json({});
  const nlohmann::json uniform = run_json({"--integrator", "uniform-acceleration"})["state_hash"];
  const nlohmann::json euler = run_json({"--integrator", "semi-implicit-euler"})["state_hash"];
  CHECK(uniform != euler);
  const bool uniform_default = hail::WorldSettings{}.integrator == hail::Integrator::UniformAcceleration;
  CHECK((uniform_default ? uniform : euler) == plain["state_hash"]);
  const nlohmann::json soft = run_json({"--solver", "soft"});
  CHECK(soft["state_hash"] != plain["state_hash"]);
  CHECK(run_json({"--solver", "soft", "--substeps", "2"})["state_hash"] != soft["state_hash"]);
  std::filesystem::remove_all(dir);
}

namespace {

/// What `command(args)` writes on file descriptor `fd` (1: stdout, where printf writes; 2: stderr),
/// and its status.
std::pair<int, std::string> output_of(int fd, Command command, const std::vector<std::string>& args,
                                      const std::string& capture) {
  std::fflush(stdout);
  std::fflush(stderr);
  const int saved = ::dup(fd);
  const int file = ::open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  REQUIRE(saved >= 0);
  REQUIRE(file >= 0);
  ::dup2(file, fd);
  ::close(file);
  int status = -1;
  try {
    status = command(args);
  } catch (...) {
    std::fflush(stdout);
    std::fflush(stderr);
    ::dup2(saved, fd);
    ::close(saved);
    throw;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  ::dup2(saved, fd);
  ::close(saved);
  std::ifstream in(capture);
  return {status, std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>())};
}

std::pair<int, std::string> stdout_of(Command command, const std::vector<std::string>& args,
                                      const std::string& capture) {
  return output_of(1, command, args, capture);
}

}  // namespace

TEST_CASE("hail-bench run --quiet prints one summary line; --dump-every needs --dump-state", "[bench][cli]") {
  const auto dir = fresh_dir("hail-test-cli-args-quiet");
  const std::string scene = (dir / "scene.json").string(), capture = (dir / "stdout.txt").string();
  std::ofstream(scene) << R"({"format": "hail-scene", "version": 1, "dt": 0.01, "steps": 4,
    "planes": [{"normal": [0, 1, 0]}],
    "spheres": [{"list": [{"position": [0, 1, 0], "radius": 0.5}, {"position": [2, 1, 0], "radius": 0.5}]}]})";
  // It printed the whole summary (14 lines) with --quiet, which silenced only the progress.
  const auto [status, quiet] = stdout_of(bench::run_command, {"--scene", scene, "--quiet", "--threads", "1"}, capture);
  CHECK(status == 0);
  INFO(quiet);
  CHECK(std::count(quiet.begin(), quiet.end(), '\n') == 1);
  CHECK(quiet.rfind(scene + ": 2 spheres, 4 steps, ", 0) == 0);
  for (const char* part : {" ms/step, worst penetration ", " m, tunnelled 0 (0 sphere-steps), NaN 0, hash "})
    CHECK(contains(quiet, part));
  const auto [full_status, full] = stdout_of(bench::run_command, {"--scene", scene, "--threads", "1"}, capture);
  CHECK(full_status == 0);
  CHECK(std::count(full.begin(), full.end(), '\n') > 5);
  // The same hash on both.
  CHECK(contains(full, "hash " + quiet.substr(quiet.size() - 17, 16)));

  CHECK(refusal(bench::run_command, {"--scene", scene, "--dump-every", "10"}) ==
        "--dump-every 10 needs --dump-state FILE.csv (the files are named after it)");
  CHECK(contains(refusal(bench::run_command, {"--dump-every", "0"}),
                 "--dump-every: must be a whole number in [1, 100000000]"));
  // A folder that cannot take the files is refused before the run.
  CHECK(contains(refusal(bench::run_command, {"--scene", scene, "--dump-state",
                                              (dir / "no-such-folder" / "s.csv").string(), "--dump-every", "2"}),
                 "does not exist"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("hail-bench run --origin D moves the scene out, --home-after K brings it back", "[bench][cli][far_origin]") {
  CHECK(
      contains(refusal(bench::run_command, {"terrain-rain", "--home-after", "3"}), "--home-after K needs --origin D"));
  CHECK(contains(refusal(bench::run_command, {"terrain-rain", "--origin", "1e9"}), "--origin"));
  const auto dir = std::filesystem::temp_directory_path() / "hail-test-cli-args-origin";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto first_row = [&](std::vector<std::string> extra) {
    const std::string csv = (dir / "state.csv").string();
    std::vector<std::string> args{"terrain-rain", "--spheres", "16",      "--steps",      "2",
                                  "--threads",    "1",         "--quiet", "--dump-state", csv};
    args.insert(args.end(), extra.begin(), extra.end());
    REQUIRE(bench::run_command(args) == 0);
    std::ifstream in(csv);
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    return row;  // id,x,y,z,...: the first sphere, in free fall for these 2 steps
  };
  const std::string home = first_row({}), out = first_row({"--origin", "1024"}),
                    back = first_row({"--origin", "1024", "--home-after", "1"});
  auto x_of = [](const std::string& row) { return std::stod(row.substr(row.find(',') + 1)); };
  CHECK(x_of(out) == x_of(home) + 1024.0);  // x 115.5 + 1024: exact, and a falling sphere keeps its x
  CHECK(x_of(back) == x_of(home));
  std::filesystem::remove_all(dir);
}

TEST_CASE("hail-bench run --terrain-as-mesh gives the heightmap's triangles to add_mesh", "[bench][cli][mesh]") {
  CHECK(contains(refusal(bench::run_command, {"implosion", "--terrain-as-mesh"}), "not to implosion"));
  CHECK(bench::run_command({"terrain-rain", "--spheres", "64", "--steps", "3", "--threads", "1", "--quiet",
                            "--terrain-as-mesh"}) == 0);
}

TEST_CASE("hail-bench (the whole command line): every command refuses an unknown flag and has --help", "[bench][cli]") {
  const auto dir = fresh_dir("hail-test-cli-args-main");
  const std::string capture = (dir / "out.txt").string();
  const auto [help_status, help] = stdout_of(bench::hail_bench, {"--help"}, capture);
  CHECK(help_status == 0);
  INFO(help);
  for (const char* command :
       {"run", "accuracy", "compare", "stress", "scale", "query", "pairs", "bvh-build", "rays", "sleep"}) {
    INFO(command);
    CHECK(contains(help, std::string("  ") + command + " "));  // hail-bench --help lists every command
    // Each command refuses an unknown flag with exit status 2, naming it (query, pairs and
    // bvh-build once ignored them), before running anything.
    const auto [status, error] = output_of(2, bench::hail_bench, {command, "--bogus-flag"}, capture);
    CHECK(status == 2);
    CHECK(error == "hail-bench: The following argument was not expected: --bogus-flag (see hail-bench " +
                       std::string(command) + " --help)\n");
    // Each has its own --help: its usage on stdout, status 0, nothing run.
    const auto [command_help_status, command_help] = stdout_of(bench::hail_bench, {command, "--help"}, capture);
    CHECK(command_help_status == 0);
    CHECK(contains(command_help, std::string("hail-bench ") + command));
    CHECK_FALSE(contains(command_help, "Subcommands:"));
  }
  CHECK(contains(help, "terrain-rain"));  // and the scenes
  // A bad value is refused naming the flag; --simd is hail-bench's own, before or after the command.
  const auto [bad_status, bad] = output_of(2, bench::hail_bench, {"run", "--steps", "2.7"}, capture);
  CHECK(bad_status == 2);
  CHECK(contains(bad, "--steps: must be a whole number in [1, 100000000], got '2.7'"));
  CHECK(output_of(2, bench::hail_bench, {"run", "--simd", "neon"}, capture).first == 2);
  CHECK(output_of(2, bench::hail_bench, {"--simd", "neon", "run"}, capture).first == 2);
  CHECK(output_of(2, bench::hail_bench, {"no-such-command"}, capture).first == 2);
  std::filesystem::remove_all(dir);
}

TEST_CASE("hail-bench sleep runs sleeping off then on and writes the share asleep per sample", "[bench][cli][sleep]") {
  const auto dir = fresh_dir("hail-test-cli-args-sleep");
  const std::string capture = (dir / "out.txt").string();
  const auto [status, out] = stdout_of(bench::sleep_command,
                                       {"bowl-pile", "--sizes", "300", "--steps", "120", "--every", "30", "--threads",
                                        "1", "--drop-spheres", "0", "--no-plot", "--out", dir.string()},
                                       capture);
  INFO(out);
  CHECK(status == 0);
  CHECK(contains(out, "      300   off "));
  CHECK(contains(out, "      300    on "));
  std::ifstream csv(dir / "asleep-300.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  REQUIRE(lines.size() == 5);  // the header and steps 30, 60, 90, 120
  CHECK(lines[0].rfind("step,time_s,asleep_share,", 0) == 0);
  CHECK(lines[4].rfind("120,2,", 0) == 0);
  CHECK(contains(refusal(bench::sleep_command, {"--sizes", "300,x"}), "--sizes entry: must be a whole number"));
}
