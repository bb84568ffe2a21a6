// The same scene gives bitwise the same state for any thread count and across runs.

#include <random>

#include "catch.h"
#include "hail/world.h"
#include "kernel/world/step_heuristics.h"
#include "sample_count.h"

namespace {

/// A 2,000-sphere cloud over a floor: mixed radii, random velocities, falling into a pile.
std::uint64_t run_cloud(int threads, int steps, hail::PairSearch search = hail::PairSearch::Automatic,
                        float radius_spread = 0.1f,
                        std::size_t tile_spheres = hail::WorldSettings{}.solver_tile_spheres) {
  hail::WorldSettings settings;
  settings.threads = threads;
  settings.pair_search = search;
  settings.solver_tile_spheres = tile_spheres;
  hail::World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.3f, .friction = 0.6f});
  world.add_plane({.normal = {1, 0, 0}, .offset = -12, .restitution = 0.3f, .friction = 0.6f});
  world.add_plane({.normal = {-1, 0, 0}, .offset = -12, .restitution = 0.3f, .friction = 0.6f});
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int k = 0; k < 2000; ++k) {
    world.add_sphere({.position = {10.0f * u(rng), 8.0f + 6.0f * u(rng), 10.0f * u(rng)},
                      .velocity = {2.0f * u(rng), 2.0f * u(rng), 2.0f * u(rng)},
                      .radius = 0.25f + radius_spread * (u(rng) + 1.0f) - 0.1f,
                      .mass = 1.0f + 0.5f * u(rng),
                      .restitution = 0.4f,
                      .friction = 0.5f});
  }
  // Under the sanitizers a fifth of the steps (sample_count.h): a race or a fault shows in any
  // step, and these runs took most of the ThreadSanitizer stage (137, 98 and 98 s of its 254).
  const int run_steps = hail::test::sample_count(steps);
  for (int k = 0; k < run_steps; ++k) world.step(1.0f / 60.0f);
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("A 2,000-sphere cloud is bitwise identical for 1 and 2 threads and across runs", "[determinism][threads]") {
  const std::uint64_t one = run_cloud(1, 600);
  const std::uint64_t two = run_cloud(2, 600);
  const std::uint64_t again = run_cloud(2, 600);
  CHECK(one == two);
  CHECK(two == again);
}

TEST_CASE("More threads than cores still give the same state", "[determinism][threads]") {
  CHECK(run_cloud(1, 120) == run_cloud(3, 120));
  CHECK(run_cloud(1, 120) == run_cloud(8, 120));
}

TEST_CASE("Solver tiles give bitwise the same state for 1, 2, 3 and 8 threads", "[determinism][solver][threads]") {
  // 128 spheres per tile: 16 tiles solved in parallel, then the contacts between them. (With
  // the default, the tests above run 8 tiles of 256.)
  const std::uint64_t one = run_cloud(1, 240, hail::PairSearch::Automatic, 0.1f, 128);
  CHECK(run_cloud(2, 240, hail::PairSearch::Automatic, 0.1f, 128) == one);
  CHECK(run_cloud(3, 240, hail::PairSearch::Automatic, 0.1f, 128) == one);
  CHECK(run_cloud(8, 240, hail::PairSearch::Automatic, 0.1f, 128) == one);
  // Tiles change the order in which contacts are solved, so the state: the tiles were used.
  CHECK(run_cloud(2, 240, hail::PairSearch::Automatic, 0.1f, 0) != one);
}

TEST_CASE("Solver tiles hold the setting's spheres, or fewer so that 16 threads or a small world get several",
          "[solver]") {
  CHECK(hail::solver_tile_size(0, 100000) == 0);  // tiles off
  CHECK(hail::solver_tile_size(2048, 100000) == 2048);
  CHECK(hail::solver_tile_size(2048, 32768) == 2048);  // 16 tiles of the setting
  CHECK(hail::solver_tile_size(2048, 16000) == 1000);  // 16 tiles for 16 threads
  CHECK(hail::solver_tile_size(2048, 4000) == 256);    // 16 tiles (15 full), none under 256
  CHECK(hail::solver_tile_size(2048, 1001) == 256);    // 4 tiles of at least 256
  CHECK(hail::solver_tile_size(2048, 301) == 151);     // two halves of a small world
  CHECK(hail::solver_tile_size(2048, 100) == hail::kMinSolverTileSpheres);
  CHECK(hail::solver_tile_size(64, 1000) == 64);
}

TEST_CASE("Step stats split the contacts into those within solver tiles and those across them", "[solver][threads]") {
  hail::WorldSettings settings;
  settings.threads = 2;
  settings.solver_tile_spheres = 64;
  hail::World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.3f, .friction = 0.6f});
  // A 10 x 10 x 4 stack of touching spheres on the floor: every sphere has neighbours in its
  // tile and, at tile edges, in the next.
  for (int y = 0; y < 4; ++y)
    for (int z = 0; z < 10; ++z)
      for (int x = 0; x < 10; ++x)
        world.add_sphere({.position = {float(x), 0.5f + float(y), float(z)}, .radius = 0.5f, .mass = 1.0f});
  for (int k = 0; k < 3; ++k) world.step(1.0f / 60.0f);
  const hail::StepStats& stats = world.last_step_stats();
  CHECK(stats.tile_contacts + stats.shared_contacts == stats.static_contacts + stats.sphere_contacts);
  CHECK(stats.shared_contacts > 0);
  CHECK(stats.tile_contacts > stats.shared_contacts);
  CHECK(stats.tile_contacts >= stats.static_contacts);  // a static contact is always its sphere's tile's
}

TEST_CASE("Every pair search gives bitwise the same simulation", "[determinism][pairs][threads]") {
  // Equal-ish radii and a 1:8 mix (0.15 .. 1.25 m), 2 threads.
  for (float spread : {0.1f, 0.55f}) {
    INFO("radius spread " << spread);
    const std::uint64_t brute = run_cloud(2, 90, hail::PairSearch::BruteForce, spread);
    CHECK(run_cloud(2, 90, hail::PairSearch::Grid, spread) == brute);
    CHECK(run_cloud(2, 90, hail::PairSearch::SweepAndPrune, spread) == brute);
    CHECK(run_cloud(2, 90, hail::PairSearch::Bvh, spread) == brute);
    CHECK(run_cloud(2, 90, hail::PairSearch::Automatic, spread) == brute);
  }
}

TEST_CASE("Automatic pair search follows the measured crossovers", "[pairs]") {
  using hail::PairSearch;
  CHECK(hail::automatic_pair_search(500, 0.5f, 0.5f) == PairSearch::BruteForce);
  CHECK(hail::automatic_pair_search(1000, 0.5f, 0.5f) == PairSearch::Grid);
  CHECK(hail::automatic_pair_search(2000, 0.25f, 5.0f) == PairSearch::BruteForce);  // mixed radii
  CHECK(hail::automatic_pair_search(8000, 0.25f, 5.0f) == PairSearch::Grid);
  CHECK(hail::automatic_pair_search(8000, 0.25f, 50.0f) == PairSearch::BruteForce);  // giants
  CHECK(hail::automatic_pair_search(16000, 0.25f, 50.0f) == PairSearch::Bvh);
}
