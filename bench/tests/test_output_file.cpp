// Every file hail-bench writes (scenes/output_file.*): checked before the run, written to a
// temporary beside the target and renamed over it only when the whole write succeeded; and the
// plot step's program started without a shell (bench/run_program.*, bench/gnuplot.*).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/accuracy_command.h"
#include "bench/compare_command.h"
#include "bench/gnuplot.h"
#include "bench/run_command.h"
#include "bench/run_program.h"
#include "bench/scale_command.h"
#include "bench/stress_command.h"
#include "tests/catch.h"
#include "tests/file_faults.h"
#include "scenes/output_file.h"

namespace bench = hail::bench;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hail-test-output-file-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::size_t files_in(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

using hail::testing::message_of;  // tests/file_faults.h

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A two-sphere scene file: a run of it takes milliseconds.
std::string small_scene(const fs::path& dir) {
  const fs::path scene = dir / "scene.json";
  write_text(scene, R"({"format": "hail-scene", "version": 1, "steps": 3,
    "spheres": [{"list": [{"position": [0, 1, 0], "radius": 0.5}, {"position": [2, 1, 0], "radius": 0.5}]}]})");
  return scene.string();
}

}  // namespace

TEST_CASE("An output file replaces the old one only when the whole write succeeded", "[bench][output]") {
  const fs::path dir = fresh_dir("atomic");
  const fs::path path = dir / "out.json";
  bench::write_file_atomically(path.string(), [](std::ostream& out) { out << "first"; });
  CHECK(read_all(path) == "first");
  bench::write_file_atomically(path.string(), [](std::ostream& out) { out << "second"; });
  CHECK(read_all(path) == "second");
  // A writer that fails half-way (an exception) or a stream that failed (a full disk) leaves
  // the old content and no temporary behind.
  CHECK_THROWS_AS(bench::write_file_atomically(path.string(),
                                               [](std::ostream& out) {
                                                 out << "half";
                                                 throw std::runtime_error("stopped");
                                               }),
                  std::runtime_error);
  CHECK(read_all(path) == "second");
  CHECK(message_of<std::runtime_error>([&] {
          bench::write_file_atomically(path.string(), [](std::ostream& out) {
            out << "cut short";
            out.setstate(std::ios::badbit);
          });
        }) == "cannot write " + path.string() + ": a write failed");
  CHECK(read_all(path) == "second");
  CHECK(files_in(dir) == 1);
  fs::remove_all(dir);
}

TEST_CASE("Writing to /dev/full fails with a message naming the path", "[bench][output]") {
  if (!fs::exists("/dev/full")) {
    WARN("no /dev/full here");
    return;
  }
  const std::string message = message_of<std::runtime_error>(
      [] { bench::write_file_atomically("/dev/full", [](std::ostream& out) { out << "x"; }); });
  CHECK(contains(message, "cannot write /dev/full: "));
  CHECK(contains(message, "No space left on device"));
  CHECK(fs::is_character_file("/dev/full"));  // written in place, never renamed over
}

TEST_CASE("Output paths are checked before the run: missing folder, a folder, the same file as an input",
          "[bench][output]") {
  const fs::path dir = fresh_dir("check");
  const std::string scene = small_scene(dir);
  const std::string nowhere = (dir / "no-such-folder" / "out.json").string();
  CHECK(message_of<std::invalid_argument>([&] { bench::check_output_paths({nowhere}); }) ==
        "cannot write " + nowhere + ": the folder " + (dir / "no-such-folder").string() + " does not exist");
  CHECK(contains(message_of<std::invalid_argument>([&] { bench::check_output_paths({dir.string()}); }),
                 "it is a folder"));
  CHECK(contains(message_of<std::invalid_argument>([&] { bench::check_output_paths({scene + "/x.csv"}); }),
                 "is not a folder"));
  // The same file however it is spelled: another path to it, a hard link; existing or not.
  const std::string spelled_otherwise = (dir / "." / "scene.json").string();
  CHECK(contains(message_of<std::invalid_argument>([&] { bench::check_output_paths({spelled_otherwise}, {scene}); }),
                 "it is the input " + scene));
  fs::create_hard_link(scene, dir / "linked.json");
  CHECK(bench::same_file((dir / "linked.json").string(), scene));
  CHECK_FALSE(bench::same_file((dir / "other.json").string(), scene));
  CHECK(contains(message_of<std::invalid_argument>([&] {
                   bench::check_output_paths({(dir / "a.json").string(), (dir / "." / "a.json").string()});
                 }),
                 "two outputs name the same file"));
  CHECK_NOTHROW(bench::check_output_paths({(dir / "new.json").string(), "", "/dev/null", "/dev/null"}, {scene}));
  CHECK_THROWS_AS(bench::prepare_output_dir(scene), std::invalid_argument);  // a file where the folder should be
  // accuracy and scale refuse such an --out before their runs (which take minutes at their defaults).
  CHECK(contains(message_of<std::invalid_argument>([&] {
                   bench::accuracy_command({"--out", scene});
                 }),
                 "cannot create the output folder " + scene));
  CHECK(contains(message_of<std::invalid_argument>([&] {
                   bench::scale_command({"--out", scene});
                 }),
                 "cannot create the output folder " + scene));
  CHECK_NOTHROW(bench::prepare_output_dir((dir / "made" / "here").string()));
  CHECK(fs::is_directory(dir / "made" / "here"));
  fs::remove_all(dir);
}

TEST_CASE("hail-bench run refuses, before running, an output that is the scene file or cannot be written",
          "[bench][output]") {
  const fs::path dir = fresh_dir("run");
  const std::string scene = small_scene(dir);
  const std::string scene_text = read_all(scene);
  // --dump-state once truncated the scene file it was asked to overwrite.
  for (const char* flag : {"--dump-state", "--json", "--trace"}) {
    INFO(flag);
    CHECK(contains(message_of<std::invalid_argument>([&] {
                     bench::run_command({"--scene", scene, flag, scene, "--quiet"});
                   }),
                   "it is the input " + scene));
    CHECK(read_all(scene) == scene_text);
  }
  // A folder that does not exist is refused before the run: 100,000 steps of 20,000 spheres
  // would take many minutes.
  const std::string nowhere = (dir / "missing" / "state.csv").string();
  CHECK(contains(
      message_of<std::invalid_argument>([&] {
        bench::run_command({"terrain-rain", "--spheres", "20000", "--steps", "100000", "--dump-state", nowhere});
      }),
      "cannot write " + nowhere));
  CHECK(contains(
      message_of<std::invalid_argument>([&] {
        bench::run_command({"--scene", scene, "--json", (dir / "same").string(), "--trace", (dir / "same").string()});
      }),
      "two outputs name the same file"));
  fs::remove_all(dir);
}

TEST_CASE("A failed write of any hail-bench output ends in an error naming the path, the old file intact",
          "[bench][output]") {
  if (!fs::exists("/dev/full")) {
    WARN("no /dev/full here");
    return;
  }
  const fs::path dir = fresh_dir("full");
  const std::string scene = small_scene(dir);
  for (const char* flag : {"--json", "--trace", "--dump-state"}) {
    INFO(flag);
    CHECK(contains(message_of<std::runtime_error>([&] {
                     bench::run_command({"--scene", scene, "--quiet", flag, "/dev/full"});
                   }),
                   "cannot write /dev/full"));
  }
  CHECK(contains(
      message_of<std::runtime_error>([&] {
        bench::run_command({"--scene", scene, "--quiet", "--ccd-both", "--repeat", "1", "--json", "/dev/full"});
      }),
      "cannot write /dev/full"));
  CHECK(contains(message_of<std::runtime_error>([&] {
                   bench::compare_command({"implosion", "--spheres", "8", "--steps", "2", "--repeat", "1", "--quiet",
                                           "--json", "/dev/full"});
                 }),
                 "cannot write /dev/full"));
  CHECK(contains(message_of<std::runtime_error>([&] {
                   bench::stress_command({"--case", "light-hit-by-heavy", "--json", "/dev/full"});
                 }),
                 "cannot write /dev/full"));
  // And a run that succeeds writes its files whole.
  const fs::path state = dir / "state.csv";
  write_text(state, "old");
  REQUIRE(bench::run_command({"--scene", scene, "--quiet", "--dump-state", state.string()}) == 0);
  CHECK(read_all(state).starts_with("id,x,y,z,vx,vy,vz,wx,wy,wz\n0,"));
  fs::remove_all(dir);
}

TEST_CASE("The plot step starts its program without a shell: quotes and ; in the folder name stay text",
          "[bench][output]") {
  const fs::path base = fresh_dir("spawn");
  // Passed through a shell (`cd 'DIR' && gnuplot ...`, as before), this name ran `touch .../pwned`.
  const fs::path weird = base / ("it's'; touch " + (base / "pwned").string() + "; echo '");
  fs::create_directories(weird);
  const bench::ProgramOutcome touched = bench::run_program({"touch", "made-here"}, weird.string());
  CHECK(touched.succeeded());
  CHECK(fs::exists(weird / "made-here"));  // run in that folder, whatever its name
  CHECK_FALSE(bench::plot_with_gnuplot(weird.string(), "script.gp", "TITLE=" + bench::gnuplot_string("a'b"), "made",
                                       "hail-test-no-such-program"));
  CHECK_FALSE(bench::plot_with_gnuplot(weird.string(), "script.gp", "X=1", "made", "false"));
  CHECK(bench::plot_with_gnuplot(weird.string(), "script.gp", "X=1", "made", "true"));
  CHECK_FALSE(fs::exists(base / "pwned"));
  const bench::ProgramOutcome missing = bench::run_program({"hail-test-no-such-program"}, base.string());
  CHECK_FALSE(missing.started);
  CHECK(contains(missing.error, "hail-test-no-such-program"));
  CHECK(bench::run_program({"false"}, base.string()).exit_status == 1);
  CHECK(bench::gnuplot_string("it's") == "'its'");
  CHECK(bench::shell_quoted("it's") == "'it'\\''s'");
  fs::remove_all(base);
}
