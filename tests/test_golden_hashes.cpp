// Golden state hashes: a short run of every built-in scene pins its final state, on 1, 2 and 3
// threads and on every SIMD path this CPU supports (as Box2D's test/test_determinism.c does).
// A change that moves the physics shows up here as a failure, and is made deliberately by
// updating one constant, with the reason in its commit. The constants are the same on every
// x86-64 machine: each SIMD path is bitwise equal to the scalar reference (docs/simd.md), the
// blocks a step is split into do not depend on the thread count, and the build pins
// -ffp-contract=off.
#include <cstdint>
#include <cstdio>
#include <string>

#include "catch.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"
#include "simd_paths.h"

namespace {

struct GoldenRun {
  const char* scene;
  std::size_t spheres;
  int steps;
  std::uint64_t hash;  ///< World::state_hash() after `steps` steps
};

// Small enough for the sanitizer stages (a few seconds in all), long enough that every scene's
// spheres meet each other and the ground (terrain-rain's first layer falls from 13 m: it lands by step 100).
constexpr GoldenRun kGoldenRuns[] = {
    {"terrain-rain", 600, 150, 0x5342e7e271b57749ull}, {"terrain-rain-dem", 300, 150, 0xac3f9142798b5cedull},
    {"bowl-pile", 400, 60, 0xd07f96c7d877ad5cull},     {"bullets", 64, 30, 0x1fe8517022760593ull},
    {"implosion", 512, 60, 0xbe76f97523ced33aull},
};

std::uint64_t run_hash(const GoldenRun& run, int threads) {
  hail::bench::SceneParams params;
  params.spheres = run.spheres;
  params.threads = threads;
  hail::bench::Scene scene = hail::bench::find_scene(run.scene).build(params);
  for (int k = 0; k < run.steps; ++k) scene.world->step(scene.dt);
  REQUIRE(scene.world->nan_count() == 0);
  return scene.world->state_hash();
}

std::string hex(std::uint64_t h) {
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

}  // namespace

TEST_CASE("Every built-in scene ends in its golden state hash on 1-3 threads and every SIMD path",
          "[determinism][golden]") {
  for (const GoldenRun& run : kGoldenRuns) {
    for (hail::SimdPath path : hail::testing::supported_paths()) {
      hail::testing::ScopedSimdPath scoped(path);
      for (int threads : {1, 2, 3}) {
        INFO(run.scene << ", " << run.spheres << " spheres, " << run.steps << " steps, " << threads << " threads, SIMD "
                       << hail::simd_path_name(path));
        CHECK(hex(run_hash(run, threads)) == hex(run.hash));
      }
    }
  }
}

TEST_CASE("Rolling resistance steps bitwise the same on 1-3 threads and every SIMD path", "[threads][rolling]") {
  // Its sweeps run the solver tiles in parallel, then the contacts across tiles in order
  // (kernel/solver/rolling_resistance.h); bowl-pile, whose pile loads its contacts.
  std::uint64_t first = 0;
  for (hail::SimdPath path : hail::testing::supported_paths()) {
    hail::testing::ScopedSimdPath scoped(path);
    for (int threads : {1, 2, 3}) {
      hail::bench::SceneParams params;
      params.spheres = 400;
      params.threads = threads;
      params.set = {"rolling_resistance=0.1"};
      hail::bench::Scene scene = hail::bench::find_scene("bowl-pile").build(params);
      REQUIRE(scene.world->settings().rolling_resistance == 0.1f);
      for (int k = 0; k < 120; ++k) scene.world->step(scene.dt);  // it lands at about step 60
      INFO(threads << " threads, SIMD " << hail::simd_path_name(path));
      if (first == 0) first = scene.world->state_hash();
      CHECK(hex(scene.world->state_hash()) == hex(first));
      // It acts: without it the pile is at 97d608dcd39187c9 after 120 steps.
      CHECK(first != 0x97d608dcd39187c9ull);
    }
  }
}

