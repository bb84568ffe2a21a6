// Collision filters in the step (include/hail/collision_filter.h, World::set_collision_filter,
// World::set_ground_filter): filtered sphere pairs pass through each other in the discrete step
// and in continuous collision, a sphere whose filter rejects the ground falls through planes and
// terrain, every pair search and thread count gives the same state, and a change takes effect
// at the next step. Also the per-sphere gravity scale's "some scale is not 1" flag, which is
// kept the same way.

#include <cmath>
#include <memory>
#include <vector>

#include "catch.h"
#include "hail/heightmap.h"
#include "hail/terrain.h"
#include "hail/world.h"

using namespace hail;

namespace {

constexpr float kDt = 1.0f / 64.0f;
constexpr CollisionFilter kTeamA{0x2u, ~0x4u};  // collides with all but team B
constexpr CollisionFilter kTeamB{0x4u, ~0x2u};  // collides with all but team A
/// The ground's filter in these tests: category 1, colliding with all but category 8.
constexpr CollisionFilter kGround{0x1u, ~0x8u};
constexpr CollisionFilter kGhost{0x8u, kAllCategories};  // passes through kGround

WorldSettings settings(Vec3 gravity, int threads = 1) {
  WorldSettings s;
  s.gravity = gravity;
  s.threads = threads;
  return s;
}

SphereDesc ball(Vec3 position, Vec3 velocity, CollisionFilter filter = {}) {
  return {.position = position, .velocity = velocity, .radius = 0.5f, .mass = 1.0f, .filter = filter};
}

/// Two spheres 4 m apart closing at `speed` each, in zero gravity, for 2 s; the first one's final x velocity.
float head_on_final_vx(CollisionFilter a, CollisionFilter b, float speed) {
  World world(settings({0, 0, 0}));
  const SphereId first = world.add_sphere(ball({-2, 0, 0}, {speed, 0, 0}, a));
  world.add_sphere(ball({2, 0, 0}, {-speed, 0, 0}, b));
  for (int k = 0; k < 128; ++k) world.step(kDt);
  return world.velocity(first).x();
}

/// Spheres of two teams (every other one) falling into a box of planes; the state hash after 90 steps.
std::uint64_t teams_pile(PairSearch search, int threads, bool ccd = true) {
  WorldSettings s = settings({0, -9.81f, 0}, threads);
  s.pair_search = search;
  s.continuous_collision = ccd;
  World world(s);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  for (const float sign : {-1.0f, 1.0f}) {
    world.add_plane({.normal = {sign, 0, 0}, .offset = -3.0f});
    world.add_plane({.normal = {0, 0, sign}, .offset = -3.0f});
  }
  for (int k = 0; k < 300; ++k) {
    const float x = -2.5f + 0.9f * static_cast<float>(k % 6), z = -2.5f + 0.9f * static_cast<float>((k / 6) % 6);
    const float y = 0.6f + 0.8f * static_cast<float>(k / 36);
    world.add_sphere({.position = {x + 0.05f * static_cast<float>(k % 3), y, z},
                      .velocity = {0, k % 7 == 0 ? -40.0f : 0.0f, 0},  // some fast: swept
                      .radius = 0.3f + 0.04f * static_cast<float>(k % 3),
                      .mass = 1.0f,
                      .filter = k % 2 == 0 ? kTeamA : kTeamB});
  }
  for (int k = 0; k < 90; ++k) world.step(1.0f / 60.0f);
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("Spheres of two teams pass through each other; spheres of one team collide", "[filters]") {
  CHECK(head_on_final_vx(kTeamA, kTeamB, 1.0f) == 1.0f);  // untouched: passed through
  CHECK(head_on_final_vx(kTeamA, kTeamA, 1.0f) < 0.0f);   // bounced back
  CHECK(head_on_final_vx(kTeamB, kTeamB, 1.0f) < 0.0f);
  CHECK(head_on_final_vx(kTeamA, CollisionFilter{}, 1.0f) < 0.0f);  // the default meets both teams
}

TEST_CASE("Fast spheres of two teams pass through each other in continuous collision too", "[filters][ccd]") {
  // 200 m/s: 3 m a step, far past a radius, so the sweep (not a contact) decides.
  CHECK(head_on_final_vx(kTeamA, kTeamB, 200.0f) == 200.0f);
  CHECK(head_on_final_vx(kTeamA, kTeamA, 200.0f) < 0.0f);
}

TEST_CASE("Category 0 collides with nothing, not even the ground", "[filters]") {
  const CollisionFilter none{0u, kAllCategories};
  CHECK(head_on_final_vx(none, CollisionFilter{}, 1.0f) == 1.0f);
  World world(settings({0, -9.81f, 0}));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  const SphereId falling = world.add_sphere(ball({0, 0.5f, 0}, {0, 0, 0}, none));
  for (int k = 0; k < 64; ++k) world.step(kDt);
  CHECK(world.position(falling).y() < -3.0f);
}

TEST_CASE("A sphere whose filter rejects the ground falls through planes; others rest on them", "[filters]") {
  for (const bool ccd : {false, true}) {
    WorldSettings s = settings({0, -9.81f, 0});
    s.continuous_collision = ccd;
    World world(s);
    world.add_plane({.normal = {0, 1, 0}, .offset = 0});
    world.set_ground_filter(kGround);
    CHECK(world.ground_filter() == kGround);
    const SphereId ghost = world.add_sphere(ball({0, 0.5f, 0}, {0, 0, 0}, kGhost));
    const SphereId solid = world.add_sphere(ball({3, 0.5f, 0}, {0, 0, 0}));
    // Fast ones: the plane bounce of the integrator and the sweep must let the ghost through too.
    const SphereId fast_ghost = world.add_sphere(ball({6, 3.0f, 0}, {0, -300.0f, 0}, kGhost));
    const SphereId fast_solid = world.add_sphere(ball({9, 3.0f, 0}, {0, -300.0f, 0}));
    for (int k = 0; k < 64; ++k) world.step(kDt);
    CHECK(world.position(ghost).y() < -3.0f);
    CHECK(world.position(fast_ghost).y() < -300.0f);
    CHECK(world.position(solid).y() > 0.45f);
    CHECK(world.position(fast_solid).y() > 0.0f);
  }
}

TEST_CASE("A sphere whose filter rejects the ground falls through terrain; others stay on it", "[filters][terrain]") {
  for (const bool ccd : {false, true}) {
    WorldSettings s = settings({0, -9.81f, 0});
    s.continuous_collision = ccd;
    World world(s);
    world.set_terrain(std::make_shared<const Terrain>(
        Heightmap::from_function(17, 17, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -8.0f, .origin_z = -8.0f},
                                 [](float x, float z) { return 0.05f * x + 0.02f * z; })));
    world.set_ground_filter(kGround);
    std::vector<SphereId> ghosts, solids;
    for (int k = 0; k < 3; ++k) {
      const float x = -4.0f + 3.0f * static_cast<float>(k);
      // The last pair fast, swept with continuous collision on (off, a fast sphere may tunnel).
      const float speed = k == 2 && ccd ? -300.0f : 0.0f;
      ghosts.push_back(world.add_sphere(ball({x, 2.0f, -2.0f}, {0, speed, 0}, kGhost)));
      solids.push_back(world.add_sphere(ball({x, 2.0f, 2.0f}, {0, speed, 0})));
    }
    // Starts inside the terrain: the start-of-step lift-out leaves a ghost where it is.
    const SphereId buried_ghost = world.add_sphere(ball({0, -1.0f, 0}, {0, 0, 0}, kGhost));
    const SphereId buried_solid = world.add_sphere(ball({1, -1.0f, 0}, {0, 0, 0}));
    world.step(kDt);
    CHECK(world.position(buried_ghost).y() < -1.0f);
    CHECK(world.position(buried_solid).y() > 0.0f);
    for (int k = 0; k < 64; ++k) world.step(kDt);
    for (const SphereId g : ghosts) CHECK(world.position(g).y() < -2.0f);
    for (const SphereId g : solids) CHECK(world.position(g).y() > -0.5f);
  }
}

TEST_CASE("Every pair search gives bitwise the same state with filters", "[filters][determinism]") {
  for (const bool ccd : {true, false}) {
    const std::uint64_t brute = teams_pile(PairSearch::BruteForce, 1, ccd);
    CHECK(teams_pile(PairSearch::Grid, 1, ccd) == brute);
    CHECK(teams_pile(PairSearch::SweepAndPrune, 1, ccd) == brute);
    CHECK(teams_pile(PairSearch::Bvh, 1, ccd) == brute);
  }
}

TEST_CASE("Filtered scenes step bitwise the same on 1 and 2 threads", "[filters][determinism][threads]") {
  CHECK(teams_pile(PairSearch::Automatic, 1) == teams_pile(PairSearch::Automatic, 2));
}

TEST_CASE("A filter changed between steps takes effect at the next step", "[filters]") {
  World world(settings({0, 0, 0}));
  // Two overlapping spheres of different teams: no contact, so they do not move.
  const SphereId a = world.add_sphere(ball({0, 0, 0}, {0, 0, 0}, kTeamA));
  const SphereId b = world.add_sphere(ball({0.8f, 0, 0}, {0, 0, 0}, kTeamB));
  world.step(kDt);
  CHECK(world.position(a).x() == 0.0f);
  CHECK(world.position(b).x() == 0.8f);
  world.set_collision_filter(b, kTeamA);
  CHECK(world.collision_filter(b) == kTeamA);
  world.step(kDt);
  CHECK(world.position(a).x() < 0.0f);  // now pushed apart
  CHECK(world.position(b).x() > 0.8f);
  // Back to the default everywhere (the world's filter flag is recounted): they still collide.
  world.set_collision_filter(a, {});
  world.set_collision_filter(b, {});
  world.set_position(a, {0, 0, 0});
  world.set_position(b, {0.8f, 0, 0});
  world.set_velocity(a, {0, 0, 0});
  world.set_velocity(b, {0, 0, 0});
  world.step(kDt);
  CHECK(world.position(a).x() < 0.0f);
}

TEST_CASE("Removing one filtered sphere keeps the others filtered", "[filters]") {
  World world(settings({0, -9.81f, 0}));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  world.set_ground_filter(kGround);
  const SphereId ghost = world.add_sphere(ball({0, 0.5f, 0}, {0, 0, 0}, kGhost));
  const SphereId other = world.add_sphere(ball({3, 0.5f, 0}, {0, 0, 0}, kGhost));
  world.set_ground_filter({});  // only the spheres' filters are non-default now: still filtering
  world.set_ground_filter(kGround);
  world.remove_sphere(other);
  for (int k = 0; k < 64; ++k) world.step(kDt);
  CHECK(world.position(ghost).y() < -3.0f);
}

TEST_CASE("Gravity scales: resetting or removing one scaled sphere keeps the others' scale", "[filters][control]") {
  World world(settings({0, -8.0f, 0}));
  const SphereId floating = world.add_sphere(ball({0, 10, 0}, {0, 0, 0}));
  const SphereId reset = world.add_sphere(ball({3, 10, 0}, {0, 0, 0}));
  const SphereId removed = world.add_sphere(ball({6, 10, 0}, {0, 0, 0}));
  for (const SphereId id : {floating, reset, removed}) world.set_gravity_scale(id, 0.0f);
  world.set_gravity_scale(reset, 1.0f);
  world.remove_sphere(removed);
  for (int k = 0; k < 8; ++k) world.step(kDt);
  CHECK(world.position(floating).y() == 10.0f);
  CHECK(world.velocity(reset).y() == -8.0f * 8 * kDt);
  world.set_gravity_scale(floating, 1.0f);  // now no scale differs from 1: the unscaled loop
  world.step(kDt);
  CHECK(world.velocity(floating).y() == -8.0f * kDt);
}
