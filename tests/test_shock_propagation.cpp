// Shock propagation (kernel/solver/shock_propagation.h): levels from the ground up, the order of the
// pass, and what it is for: a stack of very different masses stands.

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

#include "catch.h"
#include "flat_ground.h"
#include "hail/heightmap.h"
#include "hail/world.h"
#include "kernel/solver/shock_propagation.h"
#include "kernel/terrain/terrain_parts.h"

using namespace hail;
using hail::testing::flat_ground;

namespace {

SolverBody body(float inv_mass) {
  SolverBody b{};
  b.inv_mass = inv_mass;
  b.radius = 0.5f;
  return b;
}

Contact sphere_contact(std::uint32_t a, std::uint32_t b) {
  Contact c;
  c.a = a, c.b = b, c.nx = 0, c.ny = 1, c.nz = 0;
  return c;
}

}  // namespace

TEST_CASE("Shock propagation levels count contacts from the ground up", "[shock]") {
  // 0 rests on the ground, 1 on 0, 2 on 1; 3 is static, 4 rests on it; 5 and 6 float together.
  std::vector<SolverBody> bodies = {body(1), body(1), body(1), body(0), body(1), body(1), body(1), SolverBody{}};
  Contact ground;
  ground.a = 0, ground.ny = -1;
  const std::vector<Contact> contacts = {sphere_contact(1, 2), sphere_contact(5, 6), sphere_contact(0, 1), ground,
                                         sphere_contact(3, 4)};
  ShockPropagation shock;
  shock.plan(contacts, bodies, Vec3(0.0f, 1.0f, 0.0f));
  CHECK(shock.level(0) == 1);
  CHECK(shock.level(1) == 2);
  CHECK(shock.level(2) == 3);
  CHECK(shock.level(3) == 0);
  CHECK(shock.level(4) == 1);
  CHECK(shock.level(5) == ShockPropagation::kNoLevel);
  CHECK(shock.level(6) == ShockPropagation::kNoLevel);
  // Lowest level first, index order within a level; the floating pair is left out.
  const std::vector<std::uint32_t> order(shock.order().begin(), shock.order().end());
  CHECK(order == std::vector<std::uint32_t>{3, 4, 2, 0});
}

TEST_CASE("Shock propagation stops a falling stack in one pass, moving only upper bodies", "[shock]") {
  // Three spheres in a column falling at 1 m/s onto the ground: after the pass all are at rest
  // and none was pushed down (a plain sequential pass would push the lower ones into the ground).
  std::vector<SolverBody> bodies = {body(1.0f), body(1e-2f), body(1e-4f), SolverBody{}};
  for (int k = 0; k < 3; ++k) bodies[k].v[1] = -1.0f;
  Contact ground;
  ground.a = 0, ground.nx = 0, ground.ny = -1, ground.nz = 0;
  // Normals point from a to b: a is the lower sphere, so +y.
  const std::vector<Contact> contacts = {sphere_contact(1, 2), sphere_contact(0, 1), ground};
  ShockPropagation shock;
  shock.plan(contacts, bodies, Vec3(0.0f, 1.0f, 0.0f));
  shock.solve(contacts, bodies, 60.0f);
  for (int k = 0; k < 3; ++k) CHECK(bodies[k].v[1] == 0.0f);
}

TEST_CASE("A 1 : 100 : 10,000 kg stack stands with shock propagation and sinks without", "[shock]") {
  auto run = [](float shock_mass_ratio) {
    WorldSettings settings;
    settings.threads = 1;
    settings.shock_mass_ratio = shock_mass_ratio;
    World world(settings);
    world.set_terrain(flat_ground());
    const float masses[3] = {1.0f, 100.0f, 1e4f};
    SphereId bottom{};
    for (int k = 0; k < 3; ++k) {
      const SphereId id =
          world.add_sphere({.position = {32.0f, 0.5f + k * 1.0f, 32.0f}, .radius = 0.5f, .mass = masses[k]});
      if (k == 0) bottom = id;
    }
    float deepest = 0.0f;
    bool ran = false;
    for (int step = 0; step < 300; ++step) {
      world.step(1.0f / 60.0f);
      deepest = std::max(deepest, 0.5f - world.position(bottom).y());
      ran = ran || world.last_step_stats().ran.shock;
    }
    return std::pair{deepest, ran};
  };
  const auto [with_shock, ran] = run(10.0f);
  CHECK(ran);
  CHECK(with_shock < 0.01f * 0.5f);
  const auto [without, ran_without] = run(std::numeric_limits<float>::infinity());
  CHECK_FALSE(ran_without);
  CHECK(without > 0.5f);  // pressed more than a radius into the ground
}

TEST_CASE("Equal masses never run the shock pass", "[shock]") {
  World world;
  world.set_terrain(flat_ground(32));
  for (int k = 0; k < 5; ++k)
    world.add_sphere({.position = {16.0f, 0.5f + k * 1.0f, 16.0f}, .radius = 0.5f, .mass = 2.0f});
  for (int step = 0; step < 30; ++step) {
    world.step(1.0f / 60.0f);
    CHECK_FALSE(world.last_step_stats().ran.shock);
  }
}
