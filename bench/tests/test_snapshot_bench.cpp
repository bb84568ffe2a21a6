// hail-bench run --save-at STEP FILE, --restore FILE and --expect-hash H: a run saved midway
// and restored (on another thread count) ends in the hash of the whole run, and a wrong
// --expect-hash gives exit status 1.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/run_command.h"
#include "tests/catch.h"
#include "tests/file_faults.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"

namespace bench = hail::bench;

TEST_CASE("hail-bench run restores a --save-at snapshot and checks --expect-hash", "[bench][snapshot][threads]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-snapshot-bench";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "rain-20.snapshot").string();

  bench::SceneParams params;
  params.spheres = 300;
  params.threads = 1;
  bench::Scene whole = bench::find_scene("terrain-rain").build(params);
  for (int k = 0; k < 50; ++k) whole.world->step(whole.dt);
  const std::string hash = bench::hex_hash(whole.world->state_hash());

  const std::vector<std::string> common{"terrain-rain", "--spheres", "300", "--quiet"};
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    return bench::run_command(args);
  };
  CHECK(run({"--steps", "50", "--threads", "1", "--save-at", "20", file, "--expect-hash", hash}) == 0);
  REQUIRE(std::filesystem::exists(file));
  CHECK(run({"--steps", "30", "--threads", "2", "--restore", file, "--expect-hash", hash}) == 0);
  CHECK(run({"--steps", "30", "--threads", "1", "--restore", file, "--expect-hash", "0x" + hash}) == 0);
  CHECK(run({"--steps", "30", "--threads", "1", "--restore", file, "--expect-hash", "0123456789abcdef"}) == 1);
  CHECK(run({"--steps", "31", "--threads", "1", "--restore", file, "--expect-hash", hash}) == 1);
  CHECK_THROWS_AS(run({"--steps", "10", "--save-at", "20", (dir / "late.snapshot").string()}), std::invalid_argument);
  std::filesystem::remove_all(dir);
}

TEST_CASE("hail-bench run refuses an output that would overwrite an input or another output", "[bench][snapshot]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-snapshot-bench-outputs";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "maps");
  // A scene file and its heightmap in a folder of their own, and a snapshot of it.
  const std::filesystem::path source = std::filesystem::path(HAIL_SOURCE_DIR) / "data";
  std::filesystem::copy_file(source / "salish_topobathy_120x91.pgm", dir / "maps/salish.pgm");
  const std::string scene = (dir / "scene.json").string(), map = (dir / "maps/salish.pgm").string();
  {
    std::ofstream out(scene);
    out << R"({"format": "hail-scene", "version": 1, "dt": 0.0166667,
      "terrain": {"heightmap": "maps/salish.pgm", "cell_size": 1.0, "height_scale": 0.01},
      "material": {"radius": 0.5, "mass": 1.0},
      "spheres": [{"random": {"count": 20, "seed": 1, "box_min": [5, 5, 5], "box_max": [30, 10, 30]}}]})";
  }
  const std::string snap = (dir / "s.snapshot").string(), json = (dir / "out.json").string();
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"--scene", scene, "--quiet", "--threads", "1"});
    return bench::run_command(args);
  };
  REQUIRE(run({"--steps", "5", "--save-at", "3", snap}) == 0);
  const auto scene_bytes = std::filesystem::file_size(scene), map_bytes = std::filesystem::file_size(map),
             snap_bytes = std::filesystem::file_size(snap);
  auto refused = [&](std::vector<std::string> args, const std::string& needle) {
    INFO("hail-bench run --scene " << scene << " " << args.back());
    try {
      run(args);
      FAIL("expected a refusal naming '" << needle << "'");
    } catch (const std::invalid_argument& e) {
      INFO("message: " << e.what());
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  // Each of these wrote over its input (exit 0) before.
  refused({"--steps", "5", "--save-at", "3", scene}, "it is the input");
  refused({"--steps", "5", "--save-at", "3", map}, "it is the input");
  refused({"--steps", "5", "--restore", snap, "--json", snap}, "it is the input");
  refused({"--steps", "5", "--restore", snap, "--trace", snap}, "it is the input");
  refused({"--steps", "5", "--restore", snap, "--record", snap}, "it is the input");
  refused({"--steps", "5", "--save-at", "3", json, "--json", json}, "two outputs name the same file");
  refused({"--steps", "5", "--save-at", "3", json, "--record", json}, "two outputs name the same file");
  // --save-at's path is checked before the run, not at its step.
  refused({"--steps", "5", "--save-at", "3", (dir / "no-such-folder/x.snapshot").string()}, "does not exist");
  CHECK(std::filesystem::file_size(scene) == scene_bytes);
  CHECK(std::filesystem::file_size(map) == map_bytes);
  CHECK(std::filesystem::file_size(snap) == snap_bytes);
  // What a snapshot fixes is refused beside --restore (the run stepped the snapshot's settings
  // and said it ran the flag's).
  refused({"--steps", "5", "--restore", snap, "--solver", "soft"}, "--solver would be ignored");
  refused({"--steps", "5", "--restore", snap, "--sleep", "off"}, "--sleep would be ignored");
  refused({"--steps", "5", "--restore", snap, "--filters", "teams"}, "--filters teams would be ignored");
  refused({"--steps", "5", "--restore", snap, "--filters", "compare"}, "--filters compare would be ignored");
  std::filesystem::remove_all(dir);
}

TEST_CASE("hail-bench run --record replaces an old recording only once the new one is whole", "[bench][recording]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-record-atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "rain.hailrec").string();
  const std::vector<std::string> args{"terrain-rain", "--spheres", "200",     "--steps",  "20",
                                      "--threads",    "1",         "--quiet", "--record", file};
  REQUIRE(bench::run_command(args) == 0);
  const auto old_size = std::filesystem::file_size(file);
  // A disk that fills part-way (the file size limit): the run fails and the old file stays.
  // --record wrote in place and left a truncated file.
  std::vector<std::string> more = args;
  more.insert(more.end(), {"--velocities"});
  {
    const hail::testing::FileSizeLimit limit(old_size / 2);
    CHECK_THROWS(bench::run_command(more));
  }
  CHECK(std::filesystem::file_size(file) == old_size);
  for (const auto& entry : std::filesystem::directory_iterator(dir)) CHECK(entry.path().filename() == "rain.hailrec");
  std::filesystem::remove_all(dir);
}
