// hail-view's parts that need no OpenGL (hail-view-tests, ctest label "view"): the simulation
// thread hands over whole steps and its controls (pause, single step, reset, threads, spawn,
// fire) do what they say, a thread change carrying the run on bitwise; the camera's cursor ray;
// a replay's frames and speeds.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "bench/scenes/metrics.h"
#include "bench/scenes/scene_run.h"
#include "hail/recording.h"
#include "tests/catch.h"
#include "view/camera.h"
#include "view/live_simulation.h"
#include "view/replay.h"

using namespace hail;
using namespace hail::view;

namespace {

SceneFactory rain(std::size_t spheres) {
  return [spheres](const SceneChoice& c) {
    bench::SceneParams p;
    p.spheres = c.spheres.value_or(spheres);
    p.threads = c.threads;
    p.pair_search = c.pair_search.value_or(p.pair_search);
    return bench::find_scene("terrain-rain").build(p);
  };
}

/// Polls sim.latest until `done(frame)` (10 s at most).
template <class Done>
Frame wait_for(LiveSimulation& sim, Frame frame, Done done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done(frame) && std::chrono::steady_clock::now() < until) {
    sim.latest(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return frame;
}

/// The frame a plain run of the scene gives after `steps` steps, with its error figures.
Frame reference(std::size_t spheres, int threads, std::uint64_t steps) {
  bench::Scene scene = rain(spheres)({.threads = threads});
  for (std::uint64_t k = 0; k < steps; ++k) scene.world->step(scene.dt);
  Frame frame;
  capture_frame(*scene.world, 0.0, steps, frame);
  const bench::ErrorFigures errors = bench::measure_errors(scene);
  frame.deepest_overlap = std::max(errors.max_sphere_penetration, errors.max_terrain_penetration);
  frame.tunnelled = errors.tunnelled;
  return frame;
}

/// The state before the first step of a simulation made paused.
Frame first_frame(LiveSimulation& sim) {
  Frame frame;
  REQUIRE(sim.latest(frame));
  REQUIRE(frame.step == 0);
  return frame;
}

}  // namespace

TEST_CASE("The live simulation steps whole steps, and single steps, resets and thread changes keep the run", "[view]") {
  LiveSimulation sim(rain(300), {.threads = 1}, /*paused=*/true);
  sim.set_speed(100.0f);  // as fast as it goes
  Frame frame = first_frame(sim);
  sim.set_paused(false);  // runs a while ...
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step >= 5; });
  sim.set_paused(true);              // ... and stops at a step of its own choosing:
  for (int quiet = 0; quiet < 3;) {  // the last one published (none new for 3 x 100 ms)
    quiet = sim.latest(frame) ? 0 : quiet + 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::uint64_t stopped = frame.step;
  CHECK(frame.centre == reference(300, 1, stopped).centre);  // a whole step, the plain run's

  sim.set_threads(2);
  // Single steps to step 240 at least, where spheres lie on the ground and each other.
  const std::uint64_t target = std::max<std::uint64_t>(stopped + 10, 240);
  for (std::uint64_t k = stopped; k < target; ++k) sim.step_once();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == target; });
  REQUIRE(frame.step == target);
  CHECK(sim.thread_count() == 2);
  const Frame plain = reference(300, 1, target);
  CHECK(frame.centre == plain.centre);                    // bitwise, across the thread change
  CHECK(frame.deepest_overlap > 0.0);                     // (spheres in contact, so the figure can tell steps apart)
  CHECK(frame.deepest_overlap == plain.deepest_overlap);  // the error figures of that step
  CHECK(frame.tunnelled == plain.tunnelled);

  sim.reset();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == 0; });
  CHECK(frame.step == 0);
  CHECK(frame.centre == reference(300, 2, 0).centre);
}

TEST_CASE("Spawning drops a block of spheres where the ray meets the terrain; firing adds one fast sphere", "[view]") {
  LiveSimulation sim(rain(100), {.threads = 1}, /*paused=*/true);
  Frame frame = first_frame(sim);
  const std::size_t n = frame.size();
  sim.spawn_at(Vec3(0.0f, 200.0f, 0.0f), Vec3(0.0f, -1.0f, 0.0f));
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.size() == n + 27; });
  REQUIRE(frame.size() == n + 27);
  const float ground = bench::terrain_rain_height(0.0f, 0.0f);
  for (std::size_t k = n; k < n + 27; ++k) {
    CHECK(std::abs(frame.centre[3 * k]) < 3.0f);
    CHECK(frame.centre[3 * k + 1] > ground);
  }
  sim.spawn_at(Vec3(0.0f, 200.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f));  // up: meets nothing
  sim.fire(Vec3(0.0f, 40.0f, 0.0f), Vec3(1.0f, -1.0f, 0.0f), 80.0f);
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.size() == n + 28; });
  REQUIRE(frame.size() == n + 28);
  CHECK(frame.speed.back() == Approx(80.0f));

  sim.choose_for_reset(60, PairSearch::Grid);  // taken at the reset, not before
  const std::uint64_t at = frame.step;
  sim.step_once();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == at + 1; });
  REQUIRE(frame.step == at + 1);
  CHECK(frame.size() == n + 28);
  sim.reset();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == 0; });
  CHECK(frame.size() == 60);
}

TEST_CASE("The camera's ray through the middle of the view points at its target", "[view]") {
  OrbitCamera camera;
  camera.target = Eigen::Vector3f(3.0f, 1.0f, -2.0f);
  camera.distance = 25.0f;
  const auto [origin, direction] = camera.ray_through(400.0, 300.0, 800, 600);
  const Eigen::Vector3f towards = (camera.target - camera.eye()).normalized();
  CHECK(direction.dot(towards) == Approx(1.0f).margin(1e-5));
  CHECK((origin - camera.eye()).norm() < 0.1f);
  const auto [left_origin, left] = camera.ray_through(0.0, 300.0, 800, 600);
  const Eigen::Vector3f right_axis = camera.view().block<1, 3>(0, 0).transpose();
  CHECK(left.dot(right_axis) < -0.1f);  // the left edge of the view looks left
}

TEST_CASE("A replay shows the recorded positions, with speeds from velocities or frame differences", "[view]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-view-test";
  std::filesystem::create_directories(dir);
  World world(WorldSettings{.threads = 1});
  world.add_sphere({.position = {0, 0, 0}, .velocity = {3, 0, 4}, .radius = 0.5f});
  world.set_gravity_scale(world.handles()[0], 0.0f);
  for (const bool velocities : {false, true}) {
    const auto path = dir / (velocities ? "v.hailrec" : "p.hailrec");
    {
      std::ofstream file(path, std::ios::binary);
      RecordingWriter writer(file, recording_header(world, {}, "one", 0.5f, 2, velocities));
      writer.write_frame(recording_frame(world, writer.header(), 0));
      RecordingFrame moved = recording_frame(world, writer.header(), 2);
      moved.positions = {3.0f, 0.0f, 4.0f};  // 5 m in 2 steps of 0.5 s: 5 m/s
      writer.write_frame(moved);
      writer.finish();
    }
    Replay replay(path.string());
    Frame frame;
    replay.load(1, frame);
    CHECK(frame.step == 2);
    CHECK(frame.centre == std::vector<float>{3.0f, 0.0f, 4.0f});
    CHECK(frame.radius == std::vector<float>{0.5f});
    CHECK(frame.speed[0] == Approx(5.0f));
    replay.load(0, frame);
    CHECK(frame.speed[0] == Approx(velocities ? 5.0f : 0.0f));
  }
  std::filesystem::remove_all(dir);
}
