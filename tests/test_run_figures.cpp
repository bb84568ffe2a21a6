// The error figures hail-bench run reports next to its times (bench/scene_run.*).
#include "bench/scene_run.h"
#include "bench/scenes.h"
#include "catch.h"

namespace bench = hail::bench;

TEST_CASE("A run's penetration figures: the worst step, and the mean of each step's deepest", "[bench]") {
  // 1,000 spheres rain onto terrain-rain's terrain; steps 60..199 (timed) see them land, roll
  // into the valleys and touch each other, so both kinds of contact overlap at some point.
  bench::RunOptions options;
  options.steps = 200;
  options.progress = false;
  const bench::RunResult r = bench::run_scene(bench::find_scene("terrain-rain"), {.spheres = 1000, .threads = 1}, options);
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
