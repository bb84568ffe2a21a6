// The Bullet side of `hail-bench compare` (bench/peer_engine_bullet.cpp), built only with Bullet:
// its heightfield lies exactly on hail's terrain (vertical ray casts against
// Heightmap::surface_height, on the same triangle split), a dropped sphere bounces with the
// scene's effective restitution and comes to rest, spheres come back in scene order with one
// shape per radius, and Bullet's global combining callbacks are restored afterwards.

#include <btBulletDynamicsCommon.h>

#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include "bench/peer_engine_bullet.h"
#include "tests/catch.h"
#include "hail/heightmap.h"
#include "scenes/scenes.h"

using hail::Heightmap;
using hail::HeightmapParams;
using hail::bench::BulletOptions;
using hail::bench::PeerScene;
using hail::bench::PeerState;

namespace {

/// Uniform in [0, 1), deterministic.
struct Random {
  std::uint64_t state = 2026;
  float next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return float(state >> 40) * (1.0f / 16777216.0f);
  }
};

/// Height at (x, z) on the *other* split of the cell, (i, j)-(i+1, j+1): what a heightfield with
/// flipped quad edges would give.
float other_split_height(const Heightmap& map, float x, float z) {
  const HeightmapParams& p = map.params();
  const float u = (x - p.origin_x) / p.cell_x, v = (z - p.origin_z) / p.cell_z;
  const auto i = std::min<std::uint32_t>(std::uint32_t(u), map.cols() - 2),
             j = std::min<std::uint32_t>(std::uint32_t(v), map.rows() - 2);
  const float fx = u - float(i), fz = v - float(j);
  const float h00 = map.h(i, j), h10 = map.h(i + 1, j), h01 = map.h(i, j + 1), h11 = map.h(i + 1, j + 1);
  return fx >= fz ? h00 + fx * (h10 - h00) + fz * (h11 - h10) : h00 + fz * (h01 - h00) + fx * (h11 - h01);
}

struct RayCheck {
  double worst = 0.0;        ///< max |Bullet hit - hail surface|
  double other_split = 0.0;  ///< max |other split - hail surface| at the same points
  int misses = 0;
};

RayCheck cast_rays(const std::shared_ptr<const Heightmap>& map, int rays) {
  PeerScene scene;
  scene.heightmap = map;
  std::unique_ptr<hail::bench::PeerEngine> engine = hail::bench::make_bullet_engine(scene, {});
  REQUIRE(engine);
  btDiscreteDynamicsWorld* world = hail::bench::bullet_world(*engine);
  REQUIRE(world);
  const hail::HeightmapExtent e = map->extent();
  const float top = map->max_height() + 5.0f, bottom = map->min_height() - 5.0f;
  Random random;
  RayCheck check;
  for (int k = 0; k < rays; ++k) {
    const float x = e.min_x + 1e-3f + (e.max_x - e.min_x - 2e-3f) * random.next();
    const float z = e.min_z + 1e-3f + (e.max_z - e.min_z - 2e-3f) * random.next();
    const btVector3 from(x, top, z), to(x, bottom, z);
    btCollisionWorld::ClosestRayResultCallback hit(from, to);
    world->rayTest(from, to, hit);
    if (!hit.hasHit()) {
      ++check.misses;
      continue;
    }
    const double hail_y = map->surface_height(x, z);
    check.worst = std::max(check.worst, std::abs(double(hit.m_hitPointWorld.y()) - hail_y));
    check.other_split = std::max(check.other_split, std::abs(double(other_split_height(*map, x, z)) - hail_y));
  }
  return check;
}

/// Every rigid body's shape in the world, spheres only (non-static).
std::set<const btCollisionShape*> sphere_shapes(btDiscreteDynamicsWorld& world) {
  std::set<const btCollisionShape*> shapes;
  for (int k = 0; k < world.getNumCollisionObjects(); ++k) {
    const btCollisionObject* o = world.getCollisionObjectArray()[k];
    if (!o->isStaticObject()) shapes.insert(o->getCollisionShape());
  }
  return shapes;
}

}  // namespace

TEST_CASE("bullet peer: the heightfield lies on hail's terrain-rain surface (vertical ray casts)", "[bullet]") {
  auto map =
      std::make_shared<const Heightmap>(Heightmap::from_function(256, 256, {}, hail::bench::terrain_rain_height));
  const RayCheck check = cast_rays(map, 4000);
  CHECK(check.misses == 0);
  CHECK(check.worst < 1e-4);
  // The check can tell the two splits apart: the other diagonal is centimetres off here.
  CHECK(check.other_split > 1e-2);

  PeerScene scene;
  scene.heightmap = map;
  auto engine = hail::bench::make_bullet_engine(scene, {});
  CHECK(hail::bench::bullet_terrain_ray_error(*engine, *map, 32) < 1e-4);
}

TEST_CASE("bullet peer: the heightfield follows cell sizes, origin and a non-square grid", "[bullet]") {
  HeightmapParams params;
  params.cell_x = 0.5f;
  params.cell_z = 2.0f;
  params.origin_x = -10.0f;
  params.origin_y = 3.0f;
  params.origin_z = 5.0f;
  auto map = std::make_shared<const Heightmap>(Heightmap::from_function(41, 23, params, [](float x, float z) {
    return 2.0f * std::sin(0.4f * x) * std::cos(0.3f * z) + 0.5f * std::sin(0.9f * x + 0.7f * z) + 0.05f * x;
  }));
  const RayCheck check = cast_rays(map, 3000);
  CHECK(check.misses == 0);
  CHECK(check.worst < 1e-4);
  CHECK(check.other_split > 1e-2);
}

namespace {

/// A sphere (r 0.5, m 1) dropped from 5 m (lowest point) onto the plane y = 0: its vertical
/// velocity after every step of 1/60 s.
std::vector<float> drop(float sphere_restitution, float plane_restitution, bool sleeping, int steps) {
  PeerScene scene;
  scene.planes.push_back({.normal = {0, 1, 0}, .offset = 0.0f, .restitution = plane_restitution, .friction = 0.5f});
  scene.spheres.push_back(
      {.position = {0, 5.5f, 0}, .radius = 0.5f, .mass = 1.0f, .restitution = sphere_restitution, .friction = 0.5f});
  auto engine = hail::bench::make_bullet_engine(scene, {.sleeping = sleeping});
  std::vector<PeerState> state;
  std::vector<float> vy;
  for (int k = 0; k < steps; ++k) {
    engine->step(1.0f / 60.0f);
    engine->read_state(state);
    vy.push_back(state[0].velocity.y());
  }
  return vy;
}

}  // namespace

TEST_CASE("bullet peer: restitution combines by the minimum, as in hail", "[bullet]") {
  const std::vector<float> both = drop(0.8f, 0.8f, true, 200);
  // min(0.8, 1) = 0.8 whichever body has which; Bullet's own product rule would differ.
  CHECK(drop(0.8f, 1.0f, true, 200) == both);
  CHECK(drop(1.0f, 0.8f, true, 200) == both);
  const auto rebound = std::find_if(both.begin(), both.end(), [](float v) { return v > 0.0f; });
  REQUIRE(rebound != both.end());
  const float ratio = *rebound / -*(rebound - 1);
  // Bullet closes the contact step's remaining gap (13 mm here) inside the same impulse, which
  // takes gap / dt (0.8 m/s) off the rebound: 0.72 for e = 0.8; the product 0.64 would give 0.56.
  INFO("rebound / impact speed " << ratio);
  CHECK(ratio > 0.68f);
  CHECK(ratio < 0.82f);
}

TEST_CASE("bullet peer: a dropped sphere comes to rest on a plane, sleeping on and off", "[bullet]") {
  for (const bool sleeping : {true, false}) {
    PeerScene scene;
    scene.planes.push_back({.normal = {0, 1, 0}, .offset = 0.0f, .restitution = 0.5f, .friction = 0.5f});
    scene.spheres.push_back(
        {.position = {0, 5.5f, 0}, .radius = 0.5f, .mass = 1.0f, .restitution = 0.5f, .friction = 0.5f});
    auto engine = hail::bench::make_bullet_engine(scene, {.sleeping = sleeping});
    for (int k = 0; k < 600; ++k) engine->step(1.0f / 60.0f);
    std::vector<PeerState> state;
    engine->read_state(state);
    INFO("sleeping " << sleeping);
    CHECK(state[0].position.allFinite());
    CHECK(state[0].position.y() == Approx(0.5).margin(0.02));
    CHECK(std::abs(state[0].position.x()) < 1e-3f);
    CHECK(state[0].velocity.norm() < 0.05f);
    // Bullet's default deactivation puts the resting sphere to sleep; DISABLE_DEACTIVATION never.
    CHECK(hail::bench::bullet_sleeping_bodies(*hail::bench::bullet_world(*engine)) == (sleeping ? 1 : 0));
  }
}

TEST_CASE("bullet peer: friction combines by the geometric mean (case B, slide to roll)", "[bullet]") {
  // v0 = 5 m/s, mu = 0.3 on both: rolls from t* = 0.4854 s at 5/7 v0 = 3.5714 m/s. With Bullet's
  // product rule (mu = 0.09) it would still slide at 1 s, at 4.1 m/s.
  PeerScene scene;
  scene.planes.push_back({.normal = {0, 1, 0}, .offset = 0.0f, .restitution = 0.0f, .friction = 0.3f});
  scene.spheres.push_back({.position = {0, 0.5f, 0},
                           .velocity = {5, 0, 0},
                           .radius = 0.5f,
                           .mass = 1.0f,
                           .restitution = 0.0f,
                           .friction = 0.3f});
  auto engine = hail::bench::make_bullet_engine(scene, {});
  for (int k = 0; k < 60; ++k) engine->step(1.0f / 60.0f);
  std::vector<PeerState> state;
  engine->read_state(state);
  CHECK(state[0].velocity.x() == Approx(5.0 * 5.0 / 7.0).epsilon(0.02));
  CHECK(state[0].angular_velocity.z() == Approx(-5.0 * 5.0 / 7.0 / 0.5).epsilon(0.02));
}

TEST_CASE("bullet peer: spheres come back in scene order, one shape per radius, options applied", "[bullet]") {
  PeerScene scene;
  scene.gravity = {0, 0, 0};
  for (int k = 0; k < 12; ++k)
    scene.spheres.push_back({.position = {float(3 * k), 1.0f, -float(k)},
                             .velocity = {0, 0, float(k)},
                             .radius = k % 2 ? 0.25f : 0.5f,
                             .mass = k == 5 ? 0.0f : 1.0f});
  CalculateCombinedCallback restitution_before = gCalculateCombinedRestitutionCallback;
  CalculateCombinedCallback friction_before = gCalculateCombinedFrictionCallback;
  {
    auto engine = hail::bench::make_bullet_engine(scene, {.sleeping = false, .solver_iterations = 7});
    CHECK(gCalculateCombinedRestitutionCallback != restitution_before);
    btDiscreteDynamicsWorld& world = *hail::bench::bullet_world(*engine);
    CHECK(world.getSolverInfo().m_numIterations == 7);
    CHECK(sphere_shapes(world).size() == 2);
    for (int k = 0; k < world.getNumCollisionObjects(); ++k) {
      const btCollisionObject* o = world.getCollisionObjectArray()[k];
      if (!o->isStaticObject()) CHECK(o->getActivationState() == DISABLE_DEACTIVATION);
    }
    // One internal step per frame, whatever dt (no fixed-step accumulator, no substeps).
    int ticks = 0;
    world.setInternalTickCallback([](btDynamicsWorld* w, btScalar) { ++*static_cast<int*>(w->getWorldUserInfo()); },
                                  &ticks);
    for (const float dt : {1.0f / 60.0f, 1.0f / 240.0f, 0.1f}) engine->step(dt);
    CHECK(ticks == 3);
    world.setInternalTickCallback(nullptr);
    engine->step(0.5f - 1.0f / 60.0f - 1.0f / 240.0f - 0.1f);
    std::vector<PeerState> state;
    engine->read_state(state);
    REQUIRE(state.size() == scene.spheres.size());
    for (std::size_t k = 0; k < state.size(); ++k) {
      const float moved = k == 5 ? 0.0f : 0.5f * float(k);  // sphere 5 is static
      CHECK(state[k].position.x() == Approx(3.0 * double(k)));
      CHECK(state[k].position.z() == Approx(-double(k) + moved).margin(1e-4));
    }
  }
  CHECK(gCalculateCombinedRestitutionCallback == restitution_before);
  CHECK(gCalculateCombinedFrictionCallback == friction_before);
}
