// hail-bench run --save-at STEP FILE, --restore FILE and --expect-hash H: a run saved midway
// and restored (on another thread count) ends in the hash of the whole run, and a wrong
// --expect-hash gives exit status 1.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/run_command.h"
#include "bench/scenes/scene_run.h"
#include "bench/scenes/scenes.h"
#include "catch.h"

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
