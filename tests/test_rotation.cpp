// WorldSettings::rotation false: spheres never spin. Friction acts on linear velocities alone
// (a sliding sphere slows at mu g to a stop instead of rolling), no angular velocity is read,
// changed or integrated (they stay exactly 0), and the step does no angular work
// (StepParts::rotation). A frictionless scene runs the same passes either way.

#include <cmath>
#include <memory>

#include "catch.h"
#include "hail/world.h"

using namespace hail;

namespace {

bool all_angular_zero(const World& world) {
  const SphereState s = world.spheres();
  for (std::size_t i = 0; i < world.sphere_count(); ++i)
    if (s.wx[i] != 0.0f || s.wy[i] != 0.0f || s.wz[i] != 0.0f) return false;
  return true;
}

/// Spheres of two masses (1 and 20 kg: the shock pass runs) falling into a box of five planes
/// (on a terrain when there is one), with friction, and every 50th sphere fast (swept, when
/// continuous collision is compiled in).
void build_pile(World& world) {
  world.add_plane({.normal = {0, 1, 0}, .offset = -1.0f, .restitution = 0.3f, .friction = 0.6f});
  for (const float sign : {-1.0f, 1.0f}) {
    world.add_plane({.normal = {sign, 0, 0}, .offset = -5.0f, .restitution = 0.3f, .friction = 0.6f});
    world.add_plane({.normal = {0, 0, sign}, .offset = -5.0f, .restitution = 0.3f, .friction = 0.6f});
  }
  world.set_terrain(std::make_shared<const Terrain>(Heightmap::from_function(
                        21, 21, {.cell_x = 0.5f, .cell_z = 0.5f, .origin_x = -5.0f, .origin_z = -5.0f},
                        [](float x, float z) { return 0.03f * (x * x + z * z) + 0.1f * std::sin(x + z); })),
                    0.3f, 0.6f);
  for (int k = 0; k < 300; ++k) {
    const float x = -3.5f + static_cast<float>(k % 8), z = -3.5f + static_cast<float>((k / 8) % 8);
    world.add_sphere({.position = {x + 0.1f * static_cast<float>(k % 3), 2.0f + static_cast<float>(k / 64), z},
                      .velocity = {k % 50 == 7 ? 60.0f : 0.5f, k % 50 == 7 ? -200.0f : 0.0f, 0.3f},
                      .radius = 0.3f + 0.05f * static_cast<float>(k % 3),
                      .mass = k % 5 == 0 ? 20.0f : 1.0f,
                      .restitution = 0.3f,
                      .friction = 0.6f});
  }
}

}  // namespace

TEST_CASE("Without rotation a sliding sphere slows at mu g to a stop and never spins", "[rotation][known]") {
  // Case B of the known answers with rotation off: no rolling, so friction acts until the
  // sphere stops: v(t) = v0 - mu g t, stopping at t = v0 / (mu g) after v0^2 / (2 mu g).
  const float dt = 1.0f / 1000, mu = 0.3f, v0 = 5.0f, g = 9.81f;
  World world({.threads = 1, .rotation = false});
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0, .friction = mu});
  const SphereId id = world.add_sphere(
      {.position = {0, 0.5f, 0}, .velocity = {v0, 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 0, .friction = mu});
  const double t_stop = v0 / (mu * g);
  bool friction_ran = false;
  for (int k = 1; k <= 2500; ++k) {
    world.step(dt);
    const StepParts& ran = world.last_step_stats().ran;
    friction_ran |= ran.friction;
    CHECK_FALSE(ran.rotation);
    const Vec3 w = world.angular_velocity(id);
    REQUIRE((w.x() == 0.0f && w.y() == 0.0f && w.z() == 0.0f));
    const double t = k * dt;
    // Semi-implicit Euler with the friction impulse mu m g dt per step: exact at step ends to
    // rounding, until the step in which the sphere stops.
    if (t < t_stop - dt) CHECK(world.velocity(id).x() == Approx(v0 - mu * g * t).margin(1e-3));
  }
  CHECK(friction_ran);
  CHECK(world.velocity(id).norm() == 0.0f);  // stopped, not rolling on at 5/7 v0
  CHECK(world.position(id).x() == Approx(v0 * v0 / (2 * mu * g)).epsilon(2e-3));
  CHECK(std::abs(world.position(id).y() - 0.5) < 1e-3);
}

TEST_CASE("Without rotation a pile with friction, shock pass, sweep and plane impacts never spins",
          "[rotation][threads]") {
  World off({.threads = 2, .rotation = false});
  build_pile(off);
  StepParts any{};
  for (int step = 0; step < 240; ++step) {
    off.step(1.0f / 60.0f);
    const StepParts& ran = off.last_step_stats().ran;
    any.friction |= ran.friction, any.shock |= ran.shock, any.sweep |= ran.sweep, any.rotation |= ran.rotation;
    REQUIRE(all_angular_zero(off));
  }
  CHECK(any.friction);
  CHECK(any.shock);
  CHECK(any.sweep);
  CHECK_FALSE(any.rotation);  // no angular work in any step
  CHECK(off.nan_count() == 0);
  CHECK(off.kinetic_energy() < 1e3);  // it came to rest in the box (purely linear energy)
  World on({.threads = 2});
  build_pile(on);
  bool rotation_ran = false;
  for (int step = 0; step < 240; ++step) {
    on.step(1.0f / 60.0f);
    rotation_ran |= on.last_step_stats().ran.rotation;
  }
  CHECK(rotation_ran);
  CHECK_FALSE(all_angular_zero(on));  // with rotation they spin and roll
  CHECK(on.state_hash() != off.state_hash());
}

TEST_CASE("A frictionless scene steps bitwise the same with rotation on and off", "[rotation][threads]") {
  // No friction: the passes do no friction and no angular work either way (kNoFriction).
  auto run = [](bool rotation) {
    World world({.gravity = {0, 0, 0}, .threads = 2, .rotation = rotation});
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        for (int k = 0; k < 8; ++k) {
          const Vec3 p(1.5f * static_cast<float>(i) - 5.25f, 1.5f * static_cast<float>(j) - 5.25f,
                       1.5f * static_cast<float>(k) - 5.25f);
          world.add_sphere({.position = p,
                            .velocity = -5.0f * p.normalized(),
                            .radius = 0.5f,
                            .mass = 1.0f,
                            .restitution = 1.0f,
                            .friction = 0.0f});
        }
    for (int step = 0; step < 120; ++step) {
      world.step(1.0f / 60.0f);
      CHECK_FALSE(world.last_step_stats().ran.rotation);
    }
    CHECK(all_angular_zero(world));
    return world.state_hash();
  };
  CHECK(run(true) == run(false));
}

TEST_CASE("A normal impulse never spins a sphere, though friction elsewhere turns the angular passes on",
          "[rotation][sphere-sphere]") {
  // A frictionless head-on collision along a slanted line: the impulses pass through both
  // centres, so no spin. The passes take the normal part on linear velocities alone
  // (normal_relative_velocity, apply_linear_impulse); through r x p the float products of
  // parallel vectors would leave spins of rounding size. A sphere resting with friction on a
  // plane far below makes every step run the angular passes (kWithFriction) for every contact.
  // Gravity pulls both colliding spheres alike, so their relative motion stays along d.
  World world({.threads = 1});
  world.add_plane({.normal = {0, 1, 0}, .offset = -100.0f, .restitution = 0.5f, .friction = 0.5f});
  const Vec3 d = Vec3(1.0f, 2.0f, 3.0f).normalized();
  const SphereId hit =
      world.add_sphere({.position = {0, 0, 0}, .radius = 0.5f, .mass = 1.0f, .restitution = 0.7f, .friction = 0.0f});
  const SphereId mover = world.add_sphere({.position = 3.0f * d,
                                           .velocity = -4.0f * d,
                                           .radius = 0.5f,
                                           .mass = 2.0f,
                                           .restitution = 0.7f,
                                           .friction = 0.0f});
  world.add_sphere({.position = {50, -99.5f, 0}, .radius = 0.5f, .mass = 1.0f, .friction = 0.5f});
  bool angular_passes = false;
  for (int step = 0; step < 60; ++step) {
    world.step(1.0f / 60.0f);
    angular_passes |= world.last_step_stats().ran.rotation;
  }
  CHECK(angular_passes);
  CHECK(world.velocity(hit).dot(d) < -1.0f);  // they collided: the hit sphere moves off along -d
  for (const SphereId id : {hit, mover}) {
    const Vec3 w = world.angular_velocity(id);
    CHECK(w.x() == 0.0f);
    CHECK(w.y() == 0.0f);
    CHECK(w.z() == 0.0f);
  }
}
