// The error figures hail-bench run reports next to its times (bench/scene_run.*).
#include "bench/metrics.h"
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
