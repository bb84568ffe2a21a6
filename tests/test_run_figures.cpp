// The error figures hail-bench run reports next to its times (scenes/scene_run.*), the
// tunnelling counted after every step (scenes/metrics.*) and the state dumps of --dump-every.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "catch.h"
#include "scenes/metrics.h"
#include "scenes/scene_file.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"

namespace bench = hail::bench;

TEST_CASE("A run's penetration figures: the worst step, and the mean of each step's deepest", "[bench]") {
  // 1,000 spheres rain onto terrain-rain's terrain; steps 60..199 (timed) see them land, roll
  // into the valleys and touch each other, so both kinds of contact overlap at some point.
  bench::RunOptions options;
  options.steps = 200;
  options.progress = false;
  const bench::RunResult r =
      bench::run_scene(bench::find_scene("terrain-rain"), {.spheres = 1000, .threads = 1}, options);
  REQUIRE(r.warmup == 60);
  const bench::ErrorFigures& e = r.errors;
  CHECK(e.worst_sphere_penetration > 0.0);
  CHECK(e.worst_static_penetration > 0.0);
  // Each step's deepest overlap is at most the worst, and the mean of them (most steps'
  // contacts barely overlap) is below it, yet above zero.
  CHECK(e.mean_step_sphere_penetration > 0.0);
  CHECK(e.mean_step_static_penetration > 0.0);
  CHECK(e.mean_step_sphere_penetration < e.worst_sphere_penetration);
  CHECK(e.mean_step_static_penetration < e.worst_static_penetration);
}

TEST_CASE("The sphere penetration figure reads only real spheres, never the SIMD padding", "[bench]") {
  // One sphere of radius 3e19 reached the padding lanes parked at 1e18: measure_errors
  // reported 2.8e19 m of overlap for a world of one sphere. World refuses such a radius now
  // (kMaxSphereRadius), so the arrays are filled directly.
  hail::SphereSoA s;
  s.add({0, 0, 0, 0, 0, 0, 0, 0, 0, 3e19f, 1, 1, 0.5f, 0.5f, hail::kSphereFlagNone});
  REQUIRE(s.padded_size() > s.size());
  CHECK(bench::max_sphere_overlap(s) == 0.0);
  // Two real spheres still count: 0.25 m of overlap.
  s.add({1.75f, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0.5f, 0.5f, hail::kSphereFlagNone});
  CHECK(bench::max_sphere_overlap(s) == Approx(3e19));  // the giant contains the other
  hail::SphereSoA small;
  small.add({0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0.5f, 0.5f, hail::kSphereFlagNone});
  small.add({1.75f, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0.5f, 0.5f, hail::kSphereFlagNone});
  CHECK(bench::max_sphere_overlap(small) == Approx(0.25));
}

namespace {

/// A scene from scene-file text (scenes/scene_file.h), for the run figures below.
bench::Scene scene_from(const std::string& body) {
  return bench::parse_scene_text(R"({"format": "hail-scene", "version": 1, )" + body + "}", "figures.json");
}

bench::RunResult run_text(const std::string& body, int steps, int dump_every = 0, const std::string& dump_path = "") {
  bench::RunOptions options;
  options.steps = steps;
  options.progress = false;
  options.dump_state_path = dump_path;
  options.dump_every = dump_every;
  return bench::run_scene(
      "figures.json", [&] { return scene_from(body); }, options);
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("Tunnelling: a centre below the terrain inside its extent, or behind a plane, by how deep",
          "[bench][tunnelling]") {
  // A flat 4 x 4 m terrain at y = 0 and the plane y = -5 (solid below). Nothing is stepped: the
  // counter reads the spheres where they were put.
  const bench::Scene scene = scene_from(R"("terrain": {"function": "flat", "size": [5, 5]},
      "planes": [{"normal": [0, 2, 0], "offset": -10}],
      "spheres": [{"list": [{"position": [2, 1, 2]}, {"position": [2, -0.25, 2]}, {"position": [10, -1, 2]},
                            {"position": [10, -7, 2]}, {"position": [3, 0.25, 1]}]}])");
  const hail::World& world = *scene.world;
  CHECK(bench::centre_depth(world, 2, 1, 2) == Approx(-1.0));       // above the ground
  CHECK(bench::centre_depth(world, 2, -0.25f, 2) == Approx(0.25));  // under the terrain
  CHECK(bench::centre_depth(world, 10, -1, 2) == Approx(-4.0));     // outside the extent: the plane alone
  CHECK(bench::centre_depth(world, 10, -7, 2) == Approx(2.0));      // behind the plane (normalised: offset -5)
  CHECK(bench::centre_depth(world, 3, 0.25f, 1) < 0.0);             // overlapping the ground is not tunnelling
  bench::TunnellingCounter counter;
  counter.after_step(world);
  counter.after_step(world);
  const bench::TunnellingFigures& f = counter.figures();
  CHECK(f.steps == 2);
  CHECK(f.events == 4);   // two spheres, two checks each
  CHECK(f.spheres == 2);  // counted once each
  CHECK(f.worst_depth == Approx(2.0));

  // No terrain and no planes: nothing to go through, nothing counted.
  const bench::Scene open = scene_from(R"("spheres": [{"list": [{"position": [0, -100, 0]}]}])");
  bench::TunnellingCounter none;
  none.after_step(*open.world);
  CHECK(none.figures().events == 0);
  CHECK(none.figures().steps == 1);
}

TEST_CASE("Tunnelling is counted after every step of any run: a fast sphere through thin terrain without CCD",
          "[bench][tunnelling]") {
  // 10 m a step towards a flat terrain 2 m below: without continuous collision nothing stops it
  // (no contact is found that far ahead), and it falls on under the surface.
  // Appended piece by piece: GCC 12 took the chain of operator+ for an overflow (-Warray-bounds).
  const auto body = [](bool ccd) {
    std::string text = R"("gravity": [0, 0, 0], "settings": {"continuous_collision": )";
    text += ccd ? "true" : "false";
    text += R"(}, "terrain": {"function": "flat", "size": [21, 21]},
           "spheres": [{"list": [{"position": [10, 2, 10], "velocity": [0, -600, 0]}, {"position": [4, 3, 4]}]}])";
    return text;
  };
  const bench::RunResult off = run_text(body(false), 4);
  CHECK(off.tunnelling_checked);
  CHECK(off.tunnelling.steps == 4);
  CHECK(off.tunnelling.spheres == 1);
  CHECK(off.tunnelling.events >= 1);
  CHECK(off.tunnelling.worst_depth > 5.0);
  const nlohmann::json j = bench::to_json(off);
  CHECK(j["tunnelled_ever"] == 1);
  CHECK(j["tunnelling"]["events"] == off.tunnelling.events);
  CHECK(j["tunnelling"]["worst_depth"].get<double>() == off.tunnelling.worst_depth);

  const bench::RunResult on = run_text(body(true), 4);
  CHECK(on.tunnelling.events == 0);
  CHECK(on.tunnelling.spheres == 0);
}

TEST_CASE("A run's peak kinetic energy: the largest after any step, and when", "[bench]") {
  // Dropped from 20 m onto a plane that keeps nothing of the blow: the energy grows while it
  // falls (about 2 s, 120 steps) and is gone after the impact.
  const std::string body = R"("planes": [{"normal": [0, 1, 0], "restitution": 0}],
      "spheres": [{"list": [{"position": [0, 20, 0], "restitution": 0}]}])";
  const bench::RunResult r = run_text(body, 200);
  bench::Scene replay = scene_from(body);
  double peak = replay.world->kinetic_energy();
  int peak_step = 0;
  for (int k = 1; k <= 200; ++k) {
    replay.world->step(replay.dt);
    if (replay.world->kinetic_energy() > peak) peak = replay.world->kinetic_energy(), peak_step = k;
  }
  CHECK(r.energy_start == 0.0);
  CHECK(r.energy_peak == peak);
  CHECK(r.energy_peak_step == peak_step);
  CHECK(peak_step > 100);
  CHECK(peak_step < 200);
  CHECK(r.energy_peak == Approx(9.81 * 19.5).epsilon(0.05));  // m g h, to the centre at rest on the plane
  CHECK(r.errors.kinetic_energy < 1e-3 * r.energy_peak);
  const nlohmann::json j = bench::to_json(r);
  CHECK(j["kinetic_energy_peak"].get<double>() == r.energy_peak);
  CHECK(j["kinetic_energy_peak_step"] == peak_step);
}

TEST_CASE("Run state dumps (--dump-every): the state at step 0 and every K steps, each file named by its step",
          "[bench][dump]") {
  CHECK(bench::step_dump_path("out/state.csv", 60) == "out/state-000060.csv");
  CHECK(bench::step_dump_path("state.csv", 0) == "state-000000.csv");
  CHECK(bench::step_dump_path("state", 1234567) == "state-1234567");
  CHECK(bench::step_dump_path("a.b/state.x.csv", 5) == "a.b/state.x-000005.csv");

  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "hail-test-run-figures-dump";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "state.csv").string();
  const std::string body = R"("planes": [{"normal": [0, 1, 0]}],
      "spheres": [{"list": [{"position": [0, 3, 0], "velocity": [1, 0, 0]}, {"position": [0.5, 6, 0]}]}])";
  (void)run_text(body, 7, 3, path);
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"state-000000.csv", "state-000003.csv", "state-000006.csv", "state.csv"});
  // Each file is the state after that many steps, as --dump-state writes it.
  bench::Scene replay = scene_from(body);
  const std::string expected = (dir / "expected.csv").string();
  for (int step = 0; step <= 7; ++step) {
    if (step > 0) replay.world->step(replay.dt);
    if (step % 3 != 0 && step != 7) continue;
    INFO("step " << step);
    bench::write_state_csv(replay, expected);
    const std::string written = step == 7 ? path : bench::step_dump_path(path, step);
    CHECK(read_all(written) == read_all(expected));
  }
  CHECK(read_all(bench::step_dump_path(path, 3)) != read_all(bench::step_dump_path(path, 6)));
  std::filesystem::remove_all(dir);
}
