// What an embedder relies on (docs/embedding.md): the umbrella header, the version
// macros, Terrain::raycast, a World inside the host's task_arena, zero-copy spans over the
// sphere state, and the contacts of a step mapped back to sphere handles.

#include <hail/hail.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <oneapi/tbb/task_arena.h>

#include "catch.h"
#include "kernel/geometry/ray_triangle.h"

using namespace hail;

namespace {

/// Rolling hills on a 65 x 65-vertex map of 0.5 m cells, origin (-8, 1, -8).
Terrain hills() {
  const HeightmapParams params{.cell_x = 0.5f, .cell_z = 0.5f, .origin_x = -8.0f, .origin_y = 1.0f, .origin_z = -8.0f};
  return Terrain(Heightmap::from_function(
      65, 65, params, [](float x, float z) { return 1.5f * std::sin(0.4f * x) * std::cos(0.3f * z) + 0.05f * x; }));
}

/// Nearest hit over every triangle: what raycast must return.
float brute_force_t(const Terrain& terrain, const Vec3& o, const Vec3& d, float max_t) {
  const float of[3] = {o.x(), o.y(), o.z()}, df[3] = {d.x(), d.y(), d.z()};
  float best = max_t;
  for (std::uint32_t k = 0; k < terrain.triangle_count(); ++k) {
    const TerrainTriangle t = terrain.triangle(k);
    const float a[3] = {t.a.x(), t.a.y(), t.a.z()}, b[3] = {t.b.x(), t.b.y(), t.b.z()};
    const float c[3] = {t.c.x(), t.c.y(), t.c.z()};
    const float hit = ray_triangle(of, df, a, b, c);
    if (hit >= 0.0f && hit < best) best = hit;
  }
  return best;
}

}  // namespace

TEST_CASE("hail/version.h matches itself and the project version", "[embedding]") {
  CHECK(std::string(HAIL_VERSION_STRING) == std::to_string(HAIL_VERSION_MAJOR) + "." +
                                                std::to_string(HAIL_VERSION_MINOR) + "." +
                                                std::to_string(HAIL_VERSION_PATCH));
  CHECK(HAIL_VERSION == HAIL_VERSION_MAJOR * 10000 + HAIL_VERSION_MINOR * 100 + HAIL_VERSION_PATCH);
}

TEST_CASE("Terrain::raycast straight down lands on the heightmap's surface", "[embedding][terrain]") {
  const Terrain terrain = hills();
  const Heightmap& map = terrain.heightmap();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int q = 0; q < 500; ++q) {
    const float x = map.x_of(0) + u(rng) * (map.max_x() - map.x_of(0));
    const float z = map.z_of(0) + u(rng) * (map.max_z() - map.z_of(0));
    const Vec3 origin(x, map.max_height() + 10.0f, z);
    const std::optional<TerrainRayHit> hit = terrain.raycast(origin, Vec3(0, -1, 0));
    REQUIRE(hit);
    INFO("x " << x << ", z " << z);
    CHECK(hit->point.y() == Approx(map.surface_height(x, z)).margin(1e-4));
    CHECK(hit->point.x() == x);
    CHECK(hit->point.z() == z);
    CHECK(hit->t == Approx(origin.y() - hit->point.y()).margin(1e-5));
    REQUIRE(hit->triangle < terrain.triangle_count());
    CHECK(hit->normal.y() > 0.0f);
    CHECK(hit->normal.norm() == Approx(1.0f).margin(1e-5));
    CHECK(hit->normal == terrain.triangle(hit->triangle).normal);
    const TerrainTriangle t = terrain.triangle(hit->triangle);  // the hit lies on its triangle's plane
    CHECK(t.normal.dot(hit->point - t.a) == Approx(0.0f).margin(1e-4));
  }
  CHECK_THROWS_AS(terrain.triangle(static_cast<std::uint32_t>(terrain.triangle_count())), InvalidArgument);
}

TEST_CASE("Terrain::raycast gives the brute-force nearest hit for rays in any direction", "[embedding][terrain]") {
  const Terrain terrain = hills();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0;
  for (int q = 0; q < 300; ++q) {
    const Vec3 origin(10.0f * u(rng), 2.0f + 4.0f * u(rng), 10.0f * u(rng));  // above, inside and below hills
    Vec3 dir(u(rng), u(rng), u(rng));
    if (dir.norm() < 1e-3f) continue;
    dir *= 2.0f;  // not unit: t is in units of |dir|
    const float max_t = q % 3 == 0 ? std::numeric_limits<float>::infinity() : 6.0f * (u(rng) + 1.0f);
    const float want = brute_force_t(terrain, origin, dir, max_t);
    const std::optional<TerrainRayHit> got = terrain.raycast(origin, dir, max_t);
    INFO("ray " << q);
    REQUIRE(got.has_value() == (want < max_t));
    if (got) {
      ++hits;
      CHECK(got->t == want);
      CHECK((got->point - (origin + want * dir)).norm() < 1e-5f);
    }
  }
  CHECK(hits > 50);
}

TEST_CASE("Terrain::raycast misses what it should and rejects bad rays", "[embedding][terrain]") {
  const Terrain terrain = hills();
  const Vec3 down(0, -1, 0);
  CHECK_FALSE(terrain.raycast({100.0f, 10.0f, 0.0f}, down));         // outside the extent
  CHECK_FALSE(terrain.raycast({0.0f, 10.0f, 0.0f}, Vec3(0, 1, 0)));  // pointing away
  CHECK_FALSE(terrain.raycast({0.0f, 10.0f, 0.0f}, down, 1.0f));     // ends above the ground
  CHECK_FALSE(terrain.raycast({0.0f, 10.0f, 0.0f}, down, 0.0f));     // empty range
  CHECK(terrain.raycast({0.0f, 10.0f, 0.0f}, down, 20.0f));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(terrain.raycast({nan, 10.0f, 0.0f}, down), InvalidArgument);
  CHECK_THROWS_AS(terrain.raycast({0.0f, 10.0f, 0.0f}, Vec3(0, 0, 0)), InvalidArgument);
  CHECK_THROWS_AS(terrain.raycast({0.0f, 10.0f, 0.0f}, Vec3(0, -std::numeric_limits<float>::infinity(), 0)),
                  InvalidArgument);
  CHECK_THROWS_AS(terrain.raycast({0.0f, 10.0f, 0.0f}, down, -1.0f), InvalidArgument);
  CHECK_THROWS_AS(terrain.raycast({0.0f, 10.0f, 0.0f}, down, nan), InvalidArgument);
}

TEST_CASE("A World in the host's task_arena: spans alias its state and contacts name spheres",
          "[embedding][world][threads]") {
  auto terrain = std::make_shared<const Terrain>(hills());
  auto run = [&](tbb::task_arena* arena, std::uint64_t& hash) {
    const WorldSettings settings{.threads = 1};
    std::unique_ptr<World> owned =
        arena ? std::make_unique<World>(settings, *arena) : std::make_unique<World>(settings);
    World& world = *owned;
    if (arena) CHECK(world.thread_count() == arena->max_concurrency());
    world.set_terrain(terrain, 0.2f, 0.6f);
    std::vector<SphereId> ids;
    world.reserve(64);
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 8; ++k)
        ids.push_back(
            world.add_sphere({.position = {-5.0f + 1.3f * i, 5.0f + 0.1f * k, -5.0f + 1.3f * k}, .radius = 0.4f}));

    const SphereState state = world.spheres();
    CHECK(state.px.data() == world.soa().px.data());  // a view, not a copy
    CHECK(state.px.size() == 64);
    std::size_t landed = 0;
    for (int step = 0; step < 90; ++step) {  // 1.5 s, past a Morton re-sort (every 16 steps)
      world.step(1.0f / 60.0f);
      for (const Contact& c : world.last_contacts()) {
        REQUIRE(c.a < world.sphere_count());
        const SphereId who = world.id_at(c.a);
        CHECK(world.slot_of(who) == static_cast<std::int64_t>(c.a));
        if (c.b == kStaticBody) {
          CHECK(c.feature < terrain->triangle_count());  // no planes in this world
          landed += c.gap <= 0.0f;
        } else {
          CHECK(c.b < world.sphere_count());
        }
      }
    }
    CHECK(landed > 0);
    // The spans taken before the steps still point at the live state, in today's slot order.
    const SphereState now = world.spheres();
    CHECK(now.py.data() == state.py.data());
    for (SphereId id : ids) {
      const std::int64_t slot = world.slot_of(id);
      REQUIRE(slot >= 0);
      CHECK(state.py[static_cast<std::size_t>(slot)] == world.position(id).y());
      // Every sphere is on the hills, none sunk into them: the ground right under it is at
      // least most of a radius down, and about a radius for each that has come to rest. (One
      // of the 64 still rolls over a crest at 1 m/s under the uniform-acceleration integrator,
      // 0.72 m above the ground straight down: that check is for the ones at rest.)
      const Vec3 p = world.position(id);
      const std::optional<TerrainRayHit> ground = terrain->raycast(p, Vec3(0, -1, 0));
      REQUIRE(ground);
      CHECK(ground->t > 0.3f);
      if (world.velocity(id).norm() < 0.5f) CHECK(ground->t < 0.6f);
    }
    CHECK(world.nan_count() == 0);
    hash = world.state_hash();
  };
  std::uint64_t own = 0, host1 = 0, host3 = 0;
  run(nullptr, own);
  tbb::task_arena one(1), three(3);
  run(&one, host1);
  run(&three, host3);
  CHECK(host1 == own);  // the arena decides where a step runs, never what it computes
  CHECK(host3 == own);
}
