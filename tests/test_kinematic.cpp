// Kinematic spheres (SphereDesc::is_kinematic, World::set_kinematic, set_dynamic,
// move_kinematic): moved by their velocity alone, they push dynamic spheres and are not pushed,
// feel no gravity or force, pass through terrain and planes, are swept like any fast sphere,
// and give the same state on any thread count and after a snapshot.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "catch.h"
#include "hail/snapshot.h"
#include "hail/world.h"
#include "world_refusal.h"

using namespace hail;
using hail::testing::expect_rejected;
using hail::testing::kInf;
using hail::testing::kNaN;

namespace {

/// A power of two, so that free flight is exact in float.
constexpr float kDt = 1.0f / 64.0f;

WorldSettings settings(Vec3 gravity, int threads = 1) {
  WorldSettings s;
  s.gravity = gravity;
  s.threads = threads;
  return s;
}

SphereDesc paddle(Vec3 position, Vec3 velocity, float radius = 0.5f, float restitution = 0.5f) {
  return {.position = position,
          .velocity = velocity,
          .radius = radius,
          .restitution = restitution,
          .friction = 0.0f,
          .is_kinematic = true};
}

SphereDesc ball(Vec3 position, Vec3 velocity, float mass = 1.0f, float restitution = 0.5f) {
  return {.position = position,
          .velocity = velocity,
          .radius = 0.5f,
          .mass = mass,
          .restitution = restitution,
          .friction = 0.0f};
}

}  // namespace

TEST_CASE("A kinematic sphere meeting a ball head-on sends it off at (1 + e) V - e v and keeps V", "[kinematic]") {
  // Ball at v = +2 towards a paddle at V = -1, e = 0.5 (both): against an infinite mass the
  // ball leaves at (1 + e) V - e v = -1.5 - 1 = -2.5, whatever its mass, and the paddle goes on
  // at -1 exactly.
  for (const float mass : {0.25f, 1.0f, 1000.0f}) {
    World world(settings({0, 0, 0}));
    const SphereId p = world.add_sphere(paddle({1.5f, 0, 0}, {-1, 0, 0}));
    const SphereId b = world.add_sphere(ball({-1.0f, 0, 0}, {2, 0, 0}, mass));
    for (int k = 0; k < 64; ++k) world.step(kDt);
    INFO("ball mass " << mass);
    if (mass != 1000.0f) CHECK(world.velocity(b).x() == -2.5f);  // exact where 1 / m is
    CHECK(world.velocity(b).x() == Approx(-2.5f).epsilon(1e-6));
    CHECK(world.velocity(p) == Vec3(-1, 0, 0));
    CHECK(world.position(p).x() == 1.5f - 64 * kDt);  // moved by its velocity alone
    CHECK(world.position(p).y() == 0.0f);
  }
}

TEST_CASE("A kinematic sphere feels no gravity, force or impulse and passes through planes", "[kinematic]") {
  World world(settings({0, -9.81f, 0}));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  const SphereId p = world.add_sphere(paddle({0, 2, 0}, {0, -2, 0}));
  const SphereId b = world.add_sphere(ball({3, 0.5f, 0}, {0, 0, 0}));  // resting on the plane
  world.apply_impulse(p, {100, 0, 0});
  world.apply_force(p, {0, 1000, 0});
  CHECK(world.velocity(p) == Vec3(0, -2, 0));
  for (int k = 0; k < 128; ++k) world.step(kDt);  // 2 s at -2 m/s: from y = 2 to y = -2
  CHECK(world.velocity(p) == Vec3(0, -2, 0));
  CHECK(world.position(p).y() == Approx(-2.0f).margin(1e-5));
  CHECK(world.position(b).y() == Approx(0.5f).margin(0.01));  // the dynamic ball stays on the plane
  CHECK(world.last_step_stats().pushed_out == 0);
}

TEST_CASE("A rising kinematic platform lifts a ball lying on it", "[kinematic]") {
  World world(settings({0, -9.81f, 0}));
  const SphereId platform = world.add_sphere(paddle({0, 0, 0}, {0, 1, 0}, 2.0f, 0.0f));
  const SphereId b = world.add_sphere(ball({0, 2.5f, 0}, {0, 0, 0}, 1.0f, 0.0f));
  for (int k = 0; k < 128; ++k) world.step(kDt);
  const float gap = world.position(b).y() - world.position(platform).y() - 2.5f;
  CHECK(world.position(platform).y() == Approx(2.0f).margin(1e-5));
  CHECK(std::fabs(gap) < 0.01f);  // rides it: neither sinks in nor flies off
  CHECK(world.velocity(b).y() == Approx(1.0f).margin(0.05));
}

TEST_CASE("move_kinematic reaches its target in one step and pushes what is in the way", "[kinematic]") {
  World world(settings({0, 0, 0}));
  const SphereId p = world.add_sphere(paddle({0, 0, 0}, {0, 0, 0}));
  const SphereId b = world.add_sphere(ball({1.2f, 0, 0}, {0, 0, 0}));
  for (int k = 1; k <= 32; ++k) {
    const Vec3 target(0.05f * static_cast<float>(k), 0, 0);
    world.move_kinematic(p, target, kDt);
    world.step(kDt);
    CHECK((world.position(p) - target).norm() < 1e-6f);
  }
  // The paddle moved 1.6 m at 3.2 m/s into a ball 0.2 m away: it pushed the ball along.
  CHECK(world.position(b).x() > world.position(p).x() + 0.99f);
  CHECK(world.velocity(b).x() > 3.2f);
}

TEST_CASE("A fast kinematic sphere is swept: it strikes a ball it would pass in one step", "[kinematic][ccd]") {
  World world(settings({0, 0, 0}));
  // 400 m/s at dt 1/64: 6.25 m a step, the ball 3 m ahead: the discrete step would jump it.
  const SphereId p = world.add_sphere(paddle({-3, 0, 0}, {400, 0, 0}, 0.5f, 0.0f));
  const SphereId b = world.add_sphere(ball({0, 0, 0}, {0, 0, 0}, 1.0f, 0.0f));
  world.step(kDt);
  CHECK(world.velocity(p) == Vec3(400, 0, 0));
  CHECK(world.position(p).x() == Approx(-3.0f + 6.25f).margin(1e-4));
  CHECK(world.velocity(b).x() == Approx(400.0f).margin(1e-3));  // e = 0: (1 + 0) V
  CHECK(world.position(b).x() > world.position(p).x());         // in front of it, not behind
}

TEST_CASE("set_kinematic and set_dynamic switch a sphere between pushed and not pushed", "[kinematic]") {
  World world(settings({0, 0, 0}));
  const SphereId a = world.add_sphere(ball({0, 0, 0}, {0, 0, 0}, 2.0f));
  CHECK_FALSE(world.is_kinematic(a));
  world.set_kinematic(a);
  CHECK(world.is_kinematic(a));
  CHECK(world.soa().inv_mass[static_cast<std::size_t>(world.slot_of(a))] == 0.0f);
  world.add_sphere(ball({-2, 0, 0}, {2, 0, 0}));
  for (int k = 0; k < 64; ++k) world.step(kDt);
  CHECK(world.velocity(a) == Vec3::Zero());  // struck, not pushed
  CHECK(world.position(a) == Vec3::Zero());
  world.set_dynamic(a, 2.0f);
  CHECK_FALSE(world.is_kinematic(a));
  world.add_sphere(ball({0, -2, 0}, {0, 2, 0}));
  for (int k = 0; k < 64; ++k) world.step(kDt);
  CHECK(world.velocity(a).y() > 0.1f);  // now the hit moves it
}

TEST_CASE("Kinematic calls refuse what they cannot do, with the world unchanged", "[kinematic][invalid-input]") {
  World world(settings({0, -9.81f, 0}));
  const SphereId p = world.add_sphere(paddle({0, 0, 0}, {1, 0, 0}));
  const SphereId b = world.add_sphere(ball({3, 0, 0}, {0, 0, 0}));
  expect_rejected(
      world, [&] { world.add_sphere({.is_static = true, .is_kinematic = true}); }, "both is_static and is_kinematic");
  expect_rejected(
      world,
      [&] {
        world.add_sphere({.velocity = {kNaN, 0, 0}, .is_kinematic = true});
      },
      "velocity");
  expect_rejected(
      world, [&] { world.set_mass(p, 2.0f); }, "kinematic");
  expect_rejected(
      world,
      [&] {
        world.move_kinematic(b, {1, 0, 0}, kDt);
      },
      "not kinematic");
  expect_rejected(
      world,
      [&] {
        world.move_kinematic(p, {1, 0, 0}, 0.0f);
      },
      "dt");
  expect_rejected(
      world,
      [&] {
        world.move_kinematic(p, {1, 0, 0}, kNaN);
      },
      "dt");
  expect_rejected(
      world,
      [&] {
        world.move_kinematic(p, {kInf, 0, 0}, kDt);
      },
      "target");
  expect_rejected(
      world,
      [&] {
        world.move_kinematic(p, {1000, 0, 0}, 1e-6f);
      },
      "kMaxSphereSpeed");
  expect_rejected(
      world, [&] { world.set_dynamic(p, -1.0f); }, "mass");
  // A kinematic sphere takes velocities: that is how it moves.
  world.set_velocity(p, {0, 3, 0});
  CHECK(world.velocity(p) == Vec3(0, 3, 0));
}

namespace {

/// Balls rain into a box of planes while a kinematic sweeper circles through them (some steps
/// fast enough to be swept) and a second kinematic sphere passes the first; the state hash.
std::uint64_t sweeper_scene(int threads) {
  World world(settings({0, -9.81f, 0}, threads));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  for (const float sign : {-1.0f, 1.0f}) {
    world.add_plane({.normal = {sign, 0, 0}, .offset = -4.0f});
    world.add_plane({.normal = {0, 0, sign}, .offset = -4.0f});
  }
  for (int k = 0; k < 400; ++k) {
    const float x = -3.5f + 0.9f * static_cast<float>(k % 8), z = -3.5f + 0.9f * static_cast<float>((k / 8) % 8);
    world.add_sphere(
        ball({x + 0.03f * static_cast<float>(k % 5), 0.6f + 0.9f * static_cast<float>(k / 64), z}, {0, 0, 0}));
  }
  const SphereId sweeper = world.add_sphere(paddle({-3, 0.8f, 0}, {0, 0, 0}, 0.8f));
  world.add_sphere(paddle({0, 0.5f, -3}, {0, 0, 1.5f}));  // crosses the sweeper's circle: no contact between them
  for (int k = 0; k < 120; ++k) {
    const float t = static_cast<float>(k + 1) / 60.0f, speed = k % 40 == 0 ? 9.0f : 2.0f;
    world.move_kinematic(sweeper, {3.0f * std::cos(speed * t), 0.8f, 3.0f * std::sin(speed * t)}, 1.0f / 60.0f);
    world.step(1.0f / 60.0f);
  }
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("Kinematic spheres give the same state on 1 and 2 threads", "[kinematic][threads]") {
  CHECK(sweeper_scene(1) == sweeper_scene(2));
}

TEST_CASE("A snapshot keeps which spheres are kinematic", "[kinematic][snapshot]") {
  World world(settings({0, -9.81f, 0}));
  const SphereId p = world.add_sphere(paddle({0, 1, 0}, {1, 0, 0}));
  world.add_sphere(ball({2, 1, 0}, {0, 0, 0}));
  std::vector<std::byte> bytes;
  world.save(bytes);
  World restored(settings({0, -9.81f, 0}));
  restored.restore(bytes);
  CHECK(restored.is_kinematic(p));
  for (int k = 0; k < 60; ++k) world.step(kDt), restored.step(kDt);
  CHECK(restored.state_hash() == world.state_hash());
  CHECK(restored.velocity(p) == Vec3(1, 0, 0));
}
