// Values at and past the limits of what a World can represent (issue 27): each is either
// refused with hail::InvalidArgument naming it, the world unchanged, or stepped correctly.

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>

#include "catch.h"
#include "hail/world.h"
#include "world_refusal.h"

using hail::InvalidArgument;
using hail::PlaneDesc;
using hail::SphereDesc;
using hail::SphereId;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;

using namespace hail::testing;

TEST_CASE("substeps_needed counts in double and never overflows", "[invalid][limits]") {
  const WorldSettings s;  // max_substep 0.05
  CHECK(hail::substeps_needed(s, 1.0f / 60) == 1);
  CHECK(hail::substeps_needed(s, 0.1f) == 2);  // 0.1f is exactly twice 0.05f
  CHECK(hail::substeps_needed(s, 0.11f) == 3);
  CHECK(hail::substeps_needed(s, 2e8f) ==
        std::int64_t{3999999941});  // past INT_MAX (it wrapped to 1); 0.05f is a hair above 0.05
  CHECK(hail::substeps_needed(WorldSettings{.time_scale = 0}, 1.0f) == 0);
  WorldSettings extreme;
  extreme.time_scale = 3e38f;
  extreme.max_substep = std::numeric_limits<float>::denorm_min();
  CHECK(hail::substeps_needed(extreme, 3e38f) == std::numeric_limits<std::int64_t>::max());
  CHECK_THROWS_AS(hail::substeps_needed(s, kNaN), InvalidArgument);
  CHECK_THROWS_AS(hail::check_step(s, -1.0f), InvalidArgument);
  CHECK_NOTHROW(hail::check_step(s, 12.0f));                     // 240 substeps
  CHECK_THROWS_AS(hail::check_step(s, 13.0f), InvalidArgument);  // 260
}

TEST_CASE("step refuses a dt needing more than max_substeps substeps, world unchanged", "[invalid][limits]") {
  World w(WorldSettings{.threads = 1});
  w.add_sphere({.position = {0, 10, 0}});
  w.step(1.0f / 60);
  // 1e5 s: two million substeps (seconds of work); 2e8 s: a count past INT_MAX, once one substep.
  for (float dt : {1e5f, 2e8f, 3e38f})
    expect_rejected(w, [&] { w.step(dt); }, {"max_substeps", "time_scale", "max_substep", "substeps"});
  for (float dt : {0.0f, -1.0f, kNaN, kInf}) expect_rejected(w, [&] { w.step(dt); }, {"dt"});
  // time_scale counts: 1/60 s at time scale 1e4 is 167 s of simulated time.
  World fast(WorldSettings{.time_scale = 1e4f, .threads = 1});
  fast.add_sphere({});
  expect_rejected(fast, [&] { fast.step(1.0f / 60); }, {"max_substeps"});
  CHECK_THROWS_AS(World(WorldSettings{.max_substeps = 0}), InvalidArgument);
}

TEST_CASE("A step of exactly max_substeps substeps runs and falls the right distance", "[limits]") {
  WorldSettings s{.threads = 1};
  s.max_substep = 0.25f, s.max_substeps = 256;
  World w(s);
  const SphereId id = w.add_sphere({.position = {0, 0, 0}});
  w.step(64.0f);  // 256 substeps of 0.25 s
  // Semi-implicit Euler after n substeps of h: -g h^2 n (n + 1) / 2, exactly (n + 1) / n of the true fall.
  const double exact = 0.5 * 9.81 * 64.0 * 64.0;
  CHECK(-w.position(id).y() == Approx(exact * 257.0 / 256.0).epsilon(1e-4));
}

TEST_CASE("add_plane normalises a normal whose norm overflows or underflows a float", "[invalid][limits]") {
  World w(WorldSettings{.threads = 1});
  const std::size_t huge = w.add_plane({.normal = {1e20f, 0, 0}, .offset = 2e20f});  // stored a zero normal
  const std::size_t both = w.add_plane({.normal = {3e38f, 3e38f, 0}, .offset = 1});
  REQUIRE(w.planes().size() == 2);
  CHECK(w.planes()[huge].nx == 1.0f);
  CHECK(w.planes()[huge].ny == 0.0f);
  CHECK(w.planes()[huge].offset == Approx(2.0f));
  CHECK(w.planes()[both].nx == Approx(std::sqrt(0.5f)));
  CHECK(w.planes()[both].ny == Approx(std::sqrt(0.5f)));
  CHECK(std::isfinite(w.planes()[both].offset));
  // A sphere inside the half-space x < 2 of the huge normal is pushed out to x = 2 + r.
  const SphereId id = w.add_sphere({.position = {1.9f, 0, 0}, .radius = 0.5f});
  for (int k = 0; k < 30; ++k) w.step(1.0f / 60);
  CHECK(w.position(id).x() >= 2.4f);
  CHECK(w.nan_count() == 0);
  // An offset that the normal's length would blow past float range is refused.
  expect_rejected(w, [&] { w.add_plane({.normal = {1e-5f, 0, 0}, .offset = 1e35f}); }, {"offset"});
  expect_rejected(w, [&] { w.add_plane({.normal = {1e-30f, 0, 0}}); }, {"normal"});
}

TEST_CASE("add_sphere refuses radii, masses and speeds whose derived quantities leave float range",
          "[invalid][limits]") {
  World w(WorldSettings{.threads = 1});
  w.add_plane({});
  w.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}});
  w.step(1.0f / 60);
  auto sphere = [](auto edit) {
    SphereDesc d{.position = {0, 5, 0}};
    edit(d);
    return d;
  };
  // Radius 1e20 or mass 3e38: an infinite inertia, and kinetic_energy() was NaN.
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.radius = 1e20f; })); },
                  {"radius", "kMaxSphereRadius"});
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.radius = 1e-30f; })); },
                  {"radius", "kMinSphereRadius"});
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.mass = 3e38f; })); }, {"mass", "kMaxSphereMass"});
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.mass = 1e-30f; })); }, {"mass", "kMinSphereMass"});
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) {
                             d.velocity = {3e38f, 3e38f, 0};
                           })); },
                  {"velocity", "kMaxSphereSpeed"});
  expect_rejected(w, [&] { w.add_sphere(sphere([](SphereDesc& d) {
                             d.angular_velocity = {0, 1e30f, 0};
                           })); },
                  {"angular_velocity", "kMaxSphereSpin"});
  // A static sphere has no mass, velocity or spin to check: only its radius.
  expect_rejected(w,
                  [&] {
                    w.add_sphere(sphere([](SphereDesc& d) {
                      d.is_static = true;
                      d.radius = 1e20f;
                    }));
                  },
                  {"radius"});
  w.add_sphere(sphere([](SphereDesc& d) {
    d.is_static = true;
    d.mass = 3e38f;
    d.velocity = {3e38f, 0, 0};
  }));
  // At the limits, everything stays finite.
  World edge(WorldSettings{.threads = 1});
  edge.add_plane({});
  edge.add_sphere({.position = {3e6f, 1e6f, 0},
                   .velocity = {0, -1e6f, 0},
                   .angular_velocity = {1e6f, 0, 0},
                   .radius = hail::kMaxSphereRadius,
                   .mass = hail::kMaxSphereMass});
  // The smallest spheres near the origin, where a float resolves them (kSphereRadiusResolution).
  edge.add_sphere({.position = {0.2f, 0.21f, 0}, .radius = hail::kMinSphereRadius, .mass = hail::kMinSphereMass});
  edge.add_sphere({.position = {0.22f, 0.21f, 0}, .radius = hail::kMinSphereRadius, .mass = hail::kMaxSphereMass});
  edge.add_sphere({.position = {-3, 2, 0}, .radius = 1.0f, .mass = hail::kMinSphereMass});
  for (int k = 0; k < 10; ++k) edge.step(1.0f / 60);
  CHECK(edge.nan_count() == 0);
  CHECK(std::isfinite(edge.kinetic_energy()));
  CHECK(std::isfinite(edge.linear_momentum().norm()));
}

TEST_CASE("A sphere that starts inside the terrain is lifted out, as a plane pushes it out", "[terrain][limits]") {
  for (const float degrees : {0.0f, 30.0f, 60.0f}) {
    const float slope = std::tan(degrees * 3.14159265f / 180.0f);
    auto terrain = std::make_shared<const hail::Terrain>(
        hail::Heightmap::from_function(64, 64, {}, [=](float x, float) { return slope * x; }));
    for (const float depth : {0.01f, 0.5f, 5.0f}) {  // just below, a radius, ten radii (r = 0.5)
      for (const bool terrain_first : {true, false}) {
        INFO("slope " << degrees << " deg, centre " << depth << " m below the surface, terrain set "
                      << (terrain_first ? "before" : "after") << " the sphere is added");
        World w(WorldSettings{.threads = 1});
        if (terrain_first) w.set_terrain(terrain);
        const float x = 32.0f, z = 32.0f;
        const SphereId id = w.add_sphere({.position = {x, slope * x - depth, z}, .radius = 0.5f});
        if (!terrain_first) w.set_terrain(terrain);
        w.step(1.0f / 60);
        CHECK(w.last_step_stats().lifted_out == 1);
        for (int k = 0; k < 29; ++k) w.step(1.0f / 60);
        CHECK(w.last_step_stats().lifted_out == 0);
        const Vec3 p = w.position(id);
        CHECK(p.y() > terrain->heightmap().surface_height(p.x(), p.z()));
        CHECK(terrain->penetration(p.x(), p.y(), p.z(), 0.5f) < 0.05f * 0.5f);
        CHECK(w.nan_count() == 0);
      }
    }
  }
}

TEST_CASE("Spheres above the terrain, static spheres and spheres off its edge are not lifted", "[terrain][limits]") {
  auto terrain = std::make_shared<const hail::Terrain>(
      hail::Heightmap::from_function(16, 16, {}, [](float, float) { return 0.0f; }));
  World w(WorldSettings{.threads = 1});
  w.set_terrain(terrain);
  const SphereId above = w.add_sphere({.position = {8, 0.5f, 8}});
  const SphereId fixed = w.add_sphere({.position = {4, -3, 4}, .is_static = true});
  const SphereId outside = w.add_sphere({.position = {40, -3, 8}});
  w.step(1.0f / 60);
  CHECK(w.last_step_stats().lifted_out == 0);
  CHECK(w.position(fixed) == Vec3(4, -3, 4));
  CHECK(w.position(outside).y() < -3.0f);  // falls: there is no terrain under it
  CHECK(w.position(above).y() == Approx(0.5f).margin(0.01f));
  // A sphere added later is checked on the next step, even after others were removed.
  const SphereId late = w.add_sphere({.position = {10, -2, 10}});
  REQUIRE(w.remove_sphere(above));  // `late` moves into above's slot
  w.step(1.0f / 60);
  CHECK(w.last_step_stats().lifted_out == 1);
  CHECK(w.position(late).y() > 0.4f);
}

TEST_CASE("Coincident spheres: contacts capped and reported, the step completes, deterministic", "[limits]") {
  // 10,000 spheres at one point made every pair a contact (50 million) and the step ran out of
  // memory; 3,000 with a cap of 4 per sphere keep it quick.
  auto run = [](int threads, std::size_t per_sphere, int steps) {
    WorldSettings s{.threads = threads};
    s.max_sphere_contacts_per_sphere = per_sphere;
    auto w = std::make_unique<World>(s);
    w->add_plane({});
    for (int k = 0; k < 3000; ++k) w->add_sphere({.position = {0, 5, 0}, .radius = 0.5f});
    for (int k = 0; k < steps; ++k) w->step(1.0f / 60);
    return w;
  };
  const auto one = run(1, 4, 3);
  const auto two = run(2, 4, 3);
  CHECK(one->last_step_stats().sphere_contacts_capped);
  CHECK(one->last_step_stats().sphere_contacts <= 4 * 3000);
  CHECK(one->last_step_stats().sphere_contacts > 0);
  CHECK(one->nan_count() == 0);
  CHECK(one->state_hash() == two->state_hash());
  // The default cap bounds the contacts too.
  const auto full = run(2, WorldSettings{}.max_sphere_contacts_per_sphere, 1);
  CHECK(full->last_step_stats().sphere_contacts_capped);
  CHECK(full->last_step_stats().sphere_contacts <= 64 * 3000);
  CHECK(full->nan_count() == 0);
  // A world that stays within the cap reports nothing.
  World calm(WorldSettings{.threads = 1});
  for (int k = 0; k < 200; ++k)
    calm.add_sphere({.position = {float(k % 10), 0.5f + float(k / 100), float(k / 10 % 10)}});
  calm.step(1.0f / 60);
  CHECK_FALSE(calm.last_step_stats().sphere_contacts_capped);
  CHECK(calm.last_step_stats().sphere_contacts > 0);
}

TEST_CASE("max_sphere_contacts_per_sphere is validated", "[invalid][limits]") {
  WorldSettings s;
  s.max_sphere_contacts_per_sphere = 0;
  CHECK_THROWS_AS(World(s), InvalidArgument);
}

TEST_CASE("add_sphere refuses a sphere too far out for a float to resolve its radius", "[invalid][limits]") {
  World w(WorldSettings{.threads = 1});
  w.add_sphere({.position = {0, 1, 0}});
  // Floats at 3e7 are 2 m apart: a radius 0.5 sphere there moves in steps of four radii.
  expect_rejected(w,
                  [&] {
                    w.add_sphere({.position = {3e7f, 0, 0}, .radius = 0.5f});
                  },
                  {"position", "kSphereRadiusResolution"});
  expect_rejected(w, [&] { w.add_sphere({.position = {0, 0, -1.4e5f}, .radius = 0.5f}); }, {"kSphereRadiusResolution"});
  expect_rejected(w, [&] { w.add_sphere({.position = {1, 0, 0}, .radius = 1e-6f}); }, {"kSphereRadiusResolution"});
  // Within: 1.3e5 m out at radius 0.5 (floats 1/128 m apart), 3e7 m out at radius 128.
  w.add_sphere({.position = {1.3e5f, 0, 0}, .radius = 0.5f});
  w.add_sphere({.position = {3e7f, 0, 0}, .radius = 128.0f});
  CHECK(w.sphere_count() == 3);
}

TEST_CASE("set_terrain refuses a terrain too far out for a float to resolve its cells", "[invalid][limits]") {
  auto flat = [](float origin, float cell, float height) {
    hail::HeightmapParams p;
    p.origin_x = origin, p.origin_z = origin, p.cell_x = cell, p.cell_z = cell;
    return std::make_shared<const hail::Terrain>(
        hail::Heightmap::from_function(16, 16, p, [=](float, float) { return height; }));
  };
  World w(WorldSettings{.threads = 1});
  w.add_sphere({.position = {8, 1, 8}});
  // 3e7 with 1 m cells: every value turned NaN once a sphere landed.
  expect_rejected(w, [&] { w.set_terrain(flat(3e7f, 1.0f, 0.0f)); }, {"terrain", "kTerrainCellResolution"});
  expect_rejected(w, [&] { w.set_terrain(flat(0.0f, 1.0f, 3e5f)); }, {"kTerrainCellResolution"});  // heights count
  expect_rejected(w, [&] { w.set_terrain(flat(1e4f, 1e-4f, 0.0f)); }, {"kTerrainCellResolution"});
  CHECK(w.terrain() == nullptr);
  // Within: 2e5 m out with 1 m cells, 3e7 m out with 256 m cells; a sphere lands on each
  // (of a radius resolvable there: kSphereRadiusResolution).
  for (const auto& [origin, cell, r] : {std::tuple{2e5f, 1.0f, 2.0f}, std::tuple{3e7f, 256.0f, 128.0f}}) {
    World far(WorldSettings{.threads = 1});
    far.set_terrain(flat(origin, cell, 0.0f));
    const float centre = origin + 8 * cell;
    const SphereId id = far.add_sphere({.position = {centre, 1.1f * r, centre}, .radius = r});
    for (int k = 0; k < 120; ++k) far.step(1.0f / 60);
    CHECK(far.nan_count() == 0);
    CHECK(far.position(id).y() == Approx(r).margin(0.05 * r));
  }
}

TEST_CASE("reserve refuses sizes whose bytes would wrap, and the world stays usable", "[invalid][limits]") {
  // reserve(1 << 62) wrapped n * sizeof(T), took a small block for a huge one and overflowed the
  // heap; reserve(2^62 + 1) threw half-way and the next add_sphere aborted.
  World w(WorldSettings{.threads = 1});
  w.add_plane({});
  w.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}});
  w.add_sphere({.position = {2, 3, 0}});
  w.step(1.0f / 60);
  for (std::size_t n : {std::size_t{1} << 62, (std::size_t{1} << 62) + 1, std::numeric_limits<std::size_t>::max(),
                        std::size_t{hail::SphereSoA::kMaxSpheres} + 1})
    expect_rejected(
        w, [&] { w.reserve(n); }, "cannot reserve");
  const SphereId added = w.add_sphere({.position = {4, 2, 0}});
  w.reserve(1000);
  for (int k = 0; k < 30; ++k) w.step(1.0f / 60);
  CHECK(w.nan_count() == 0);
  CHECK(w.sphere_count() == 3);
  CHECK(w.position(added).y() < 2.0f);

  hail::AlignedArray<float> array(4, 1.0f);
  CHECK_THROWS_AS(array.reserve(hail::AlignedArray<float>::max_size() + 1), std::length_error);
  CHECK_THROWS_AS(array.reserve(std::numeric_limits<std::size_t>::max() / 2), std::length_error);
  CHECK(array.size() == 4);
  CHECK(array[3] == 1.0f);
}
