// World's calls that drive spheres from a game (include/hail/world.h, "Driving spheres from a
// game"): each setter's effect, exact where the answer is closed-form; each refusal, with the
// world unchanged; a teleport's dropped warm start; forces cleared after a step; user data
// through the Morton re-sort and removals; the same state on any thread count.

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "world_refusal.h"

using namespace hail;
using hail::testing::expect_rejected;
using hail::testing::kInf;
using hail::testing::kNaN;

namespace {

/// dt and gravity powers of two, so that free flight is exact in float.
constexpr float kDt = 1.0f / 64.0f;

WorldSettings settings_with(Vec3 gravity, bool rotation = true, int threads = 1) {
  WorldSettings s;
  s.gravity = gravity;
  s.rotation = rotation;
  s.threads = threads;
  return s;
}

SphereDesc ball(Vec3 position, float mass = 2.0f, float radius = 0.5f) {
  return {.position = position, .radius = radius, .mass = mass};
}

}  // namespace

TEST_CASE("set_position, set_velocity and set_angular_velocity set exactly what they are given", "[control]") {
  World world(settings_with({0, 0, 0}));
  const SphereId id = world.add_sphere(ball({0, 0, 0}));
  world.set_position(id, {1.25f, -3.5f, 7.0f});
  world.set_velocity(id, {0.5f, 2.0f, -1.0f});
  world.set_angular_velocity(id, {0.0f, 3.0f, 0.25f});
  CHECK(world.position(id) == Vec3(1.25f, -3.5f, 7.0f));
  CHECK(world.velocity(id) == Vec3(0.5f, 2.0f, -1.0f));
  CHECK(world.angular_velocity(id) == Vec3(0.0f, 3.0f, 0.25f));
  world.step(kDt);  // no gravity, nothing near: it flies straight on
  CHECK(world.position(id) == Vec3(1.25f + 0.5f * kDt, -3.5f + 2.0f * kDt, 7.0f - kDt));
}

TEST_CASE("An impulse J on a mass m changes its velocity by exactly J / m", "[control]") {
  World world(settings_with({0, 0, 0}));
  const SphereId id = world.add_sphere({.position = {0, 0, 0}, .velocity = {1, 0, 0}, .mass = 2.0f});
  world.apply_impulse(id, {3.0f, -4.0f, 0.5f});
  CHECK(world.velocity(id) == Vec3(2.5f, -2.0f, 0.25f));
  CHECK(world.angular_velocity(id) == Vec3::Zero());
  world.set_mass(id, 4.0f);  // the next impulse sees the new mass
  world.apply_impulse(id, {2.0f, 0.0f, 0.0f});
  CHECK(world.velocity(id) == Vec3(3.0f, -2.0f, 0.25f));
}

TEST_CASE("An impulse at a point off the centre also spins the sphere by (r x J) / I", "[control]") {
  World world(settings_with({0, 0, 0}));
  const SphereId id = world.add_sphere(ball({1, 2, 3}, 2.0f, 0.5f));
  const float inv_inertia = world.soa().inv_inertia[static_cast<std::size_t>(world.slot_of(id))];
  CHECK(inv_inertia == 1.0f / (0.4f * 2.0f * 0.5f * 0.5f));
  // r = (0.5, 0, 0), J = (0, 0, 1): r x J = (0, -0.5, 0).
  world.apply_impulse_at(id, {0, 0, 1}, {1.5f, 2, 3});
  CHECK(world.velocity(id) == Vec3(0, 0, 0.5f));
  CHECK(world.angular_velocity(id) == Vec3(0, -0.5f * inv_inertia, 0));
  CHECK(world.angular_velocity(id).y() == Approx(-2.5f));

  World flat(settings_with({0, 0, 0}, /*rotation=*/false));
  const SphereId f = flat.add_sphere(ball({1, 2, 3}));
  flat.apply_impulse_at(f, {0, 0, 1}, {1.5f, 2, 3});  // without rotation: the linear part only
  CHECK(flat.velocity(f) == Vec3(0, 0, 0.5f));
  CHECK(flat.angular_velocity(f) == Vec3::Zero());
}

TEST_CASE("A force acts for one step beside gravity, then is cleared; a substepped step applies it in each",
          "[control]") {
  World world(settings_with({0, -8, 0}));
  const SphereId id = world.add_sphere(ball({0, 10, 0}, 2.0f));
  world.apply_force(id, {3.0f, 0, 0});
  world.apply_force(id, {1.0f, 0, 0});  // accumulated: 4 N
  world.step(kDt);
  // F dt / m = 4 / 64 / 2 = 1/32 beside gravity's -8 / 64 = -1/8.
  CHECK(world.velocity(id) == Vec3(1.0f / 32.0f, -1.0f / 8.0f, 0));
  world.step(kDt);  // cleared: only gravity now
  CHECK(world.velocity(id) == Vec3(1.0f / 32.0f, -2.0f / 8.0f, 0));

  WorldSettings fine = settings_with({0, 0, 0});
  fine.max_substep = kDt;
  World substepped(fine);
  const SphereId s = substepped.add_sphere(ball({0, 10, 0}, 2.0f));
  substepped.apply_force(s, {4.0f, 0, 0});
  substepped.step(4.0f * kDt);  // four substeps of 1/64 s, each adding 1/32 m/s
  CHECK(substepped.velocity(s) == Vec3(4.0f / 32.0f, 0, 0));
  substepped.step(4.0f * kDt);
  CHECK(substepped.velocity(s) == Vec3(4.0f / 32.0f, 0, 0));
}

TEST_CASE("A torque spins a sphere for one step by T dt / I", "[control]") {
  World world(settings_with({0, 0, 0}));
  const SphereId id = world.add_sphere(ball({0, 0, 0}, 2.0f, 0.5f));
  const float inv_inertia = world.soa().inv_inertia[static_cast<std::size_t>(world.slot_of(id))];
  world.apply_torque(id, {0, 0, 1.0f});
  world.step(kDt);
  CHECK(world.angular_velocity(id) == Vec3(0, 0, 1.0f * (inv_inertia * kDt)));
  world.step(kDt);
  CHECK(world.angular_velocity(id) == Vec3(0, 0, 1.0f * (inv_inertia * kDt)));
}

TEST_CASE("Gravity scale 0 floats, 2 falls twice as far as 1: closed-form positions", "[control]") {
  for (const Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::UniformAcceleration}) {
    WorldSettings settings = settings_with({0, -8, 0});
    settings.integrator = integrator;
    World world(settings);
    const SphereId still = world.add_sphere(ball({-10, 100, 0}));
    const SphereId normal = world.add_sphere(ball({0, 100, 0}));
    const SphereId heavy = world.add_sphere(ball({10, 100, 0}));
    world.set_gravity_scale(still, 0.0f);
    world.set_gravity_scale(heavy, 2.0f);
    constexpr int kSteps = 10;
    for (int k = 0; k < kSteps; ++k) world.step(kDt);
    CHECK(world.position(still) == Vec3(-10, 100, 0));
    CHECK(world.velocity(still) == Vec3::Zero());
    CHECK(world.velocity(heavy) == Vec3(0, 2.0f * -8.0f * kDt * kSteps, 0));
    if (integrator == Integrator::SemiImplicitEuler) {
      // v_k = k g s dt, y_k = y_0 + g s dt^2 k (k + 1) / 2, exact in float here.
      const float drop = -8.0f * kDt * kDt * kSteps * (kSteps + 1) / 2.0f;
      CHECK(world.position(normal) == Vec3(0, 100 + drop, 0));
      CHECK(world.position(heavy) == Vec3(10, 100 + 2.0f * drop, 0));
    } else {
      // The parabola, y = y_0 + g s t^2 / 2 (to float rounding over the steps).
      const float drop = -8.0f * (kDt * kSteps) * (kDt * kSteps) / 2.0f;
      CHECK(world.position(normal).y() == Approx(100 + drop).epsilon(1e-6));
      CHECK(world.position(heavy).y() == Approx(100 + 2.0f * drop).epsilon(1e-6));
      CHECK(world.position(heavy).x() == 10.0f);
    }
  }
}

TEST_CASE("Material, mass and radius changes reach the sphere's arrays", "[control]") {
  World world(settings_with({0, -9.81f, 0}));
  const SphereId id = world.add_sphere(ball({0, 5, 0}, 2.0f, 0.5f));
  world.set_restitution(id, 0.9f);
  world.set_friction(id, 1.5f);
  world.set_mass(id, 8.0f);
  world.set_radius(id, 0.25f);
  const SphereSoA& s = world.soa();
  const auto i = static_cast<std::size_t>(world.slot_of(id));
  CHECK(s.restitution[i] == 0.9f);
  CHECK(s.friction[i] == 1.5f);
  CHECK(s.inv_mass[i] == 0.125f);
  CHECK(s.radius[i] == 0.25f);
  CHECK(s.inv_inertia[i] == 1.0f / (0.4f * 8.0f * 0.25f * 0.25f));
}

TEST_CASE("Impulses, forces and torques on a static sphere are ignored; velocity and mass are refused", "[control]") {
  World world(settings_with({0, -9.81f, 0}));
  const SphereId wall = world.add_sphere({.position = {0, 0, 0}, .is_static = true});
  world.apply_impulse(wall, {5, 5, 5});
  world.apply_impulse_at(wall, {5, 5, 5}, {0.5f, 0, 0});
  world.apply_force(wall, {100, 0, 0});
  world.apply_torque(wall, {0, 100, 0});
  world.step(kDt);
  CHECK(world.position(wall) == Vec3::Zero());
  CHECK(world.velocity(wall) == Vec3::Zero());
  CHECK(world.angular_velocity(wall) == Vec3::Zero());
  expect_rejected(
      world,
      [&] {
        world.set_velocity(wall, {1, 0, 0});
      },
      "static");
  expect_rejected(
      world,
      [&] {
        world.set_angular_velocity(wall, {1, 0, 0});
      },
      "static");
  expect_rejected(
      world, [&] { world.set_mass(wall, 1.0f); }, "static");
  CHECK(world.soa().inv_mass[0] == 0.0f);
  world.set_position(wall, {3, 0, 0});  // a static obstacle may be moved
  CHECK(world.position(wall) == Vec3(3, 0, 0));
}

TEST_CASE("Every control call refuses a bad value or a stale handle and leaves the world unchanged",
          "[control][invalid]") {
  World world(settings_with({0, -9.81f, 0}));
  const SphereId id = world.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}, .radius = 0.5f, .mass = 2.0f});
  const SphereId gone = world.add_sphere(ball({5, 1, 0}));
  world.step(kDt);
  REQUIRE(world.remove_sphere(gone));

  expect_rejected(
      world,
      [&] {
        world.set_position(id, {kNaN, 0, 0});
      },
      "sphere position must be finite");
  expect_rejected(
      world,
      [&] {
        world.set_position(id, {1e6f, 0, 0});
      },
      "kSphereRadiusResolution");
  expect_rejected(
      world,
      [&] {
        world.set_velocity(id, {kInf, 0, 0});
      },
      "sphere velocity must be finite");
  expect_rejected(
      world,
      [&] {
        world.set_velocity(id, {2e6f, 0, 0});
      },
      "kMaxSphereSpeed");
  expect_rejected(
      world,
      [&] {
        world.set_angular_velocity(id, {0, kNaN, 0});
      },
      "angular_velocity must be finite");
  expect_rejected(
      world,
      [&] {
        world.set_angular_velocity(id, {0, 2e6f, 0});
      },
      "kMaxSphereSpin");
  expect_rejected(
      world,
      [&] {
        world.apply_impulse(id, {kNaN, 0, 0});
      },
      "impulse must be finite");
  expect_rejected(
      world,
      [&] {
        world.apply_impulse(id, {4e6f, 0, 0});
      },
      "kMaxSphereSpeed");  // 2e6 m/s
  expect_rejected(
      world,
      [&] {
        world.apply_impulse_at(id, {1, 0, 0}, {kInf, 0, 0});
      },
      "impulse point");
  expect_rejected(
      world,
      [&] {
        world.apply_impulse_at(id, {0, 0, 1e6f}, {1e6f, 1, 0});
      },
      "kMaxSphereSpin");
  expect_rejected(
      world,
      [&] {
        world.apply_force(id, {0, kNaN, 0});
      },
      "force must be finite");
  // A force that would take the sphere past the speed limit within the longest step is refused
  // (3e38 N was accepted and turned it NaN); so is a sum of forces that would (2 kg: 1e5 N
  // gives 5e4 m/s^2, 6.4e5 m/s over 12.8 s; twice that is over 1e6).
  expect_rejected(
      world,
      [&] {
        world.apply_force(id, {3e38f, 0, 0});
      },
      "accumulated force");
  world.apply_force(id, {1e5f, 0, 0});
  expect_rejected(
      world,
      [&] {
        world.apply_force(id, {1e5f, 0, 0});
      },
      "accumulated force");
  expect_rejected(
      world,
      [&] {
        world.apply_torque(id, {0, 0, kInf});
      },
      "torque must be finite");
  expect_rejected(
      world, [&] { world.set_restitution(id, 1.5f); }, "restitution must be in [0, 1]");
  expect_rejected(
      world, [&] { world.set_friction(id, -1.0f); }, "friction must be finite and >= 0");
  expect_rejected(
      world, [&] { world.set_mass(id, 0.0f); }, "mass must be finite and > 0");
  expect_rejected(
      world, [&] { world.set_mass(id, 1e13f); }, "kMaxSphereMass");
  expect_rejected(
      world, [&] { world.set_radius(id, kNaN); }, "radius must be finite");
  expect_rejected(
      world, [&] { world.set_radius(id, 2e6f); }, "kMaxSphereRadius");
  expect_rejected(
      world, [&] { world.set_gravity_scale(id, kNaN); }, "gravity scale");
  expect_rejected(
      world, [&] { world.set_gravity_scale(id, -2e6f); }, "kMaxGravityScale");
  const SphereSoA& s = world.soa();
  CHECK(s.inv_mass[0] == 0.5f);
  CHECK(s.radius[0] == 0.5f);
  CHECK(s.restitution[0] == 0.5f);
  CHECK(s.gravity_scale[0] == 1.0f);

  // A far sphere cannot shrink below what floats there resolve.
  World far(settings_with({0, 0, 0}));
  const SphereId out = far.add_sphere(ball({100000.0f, 0, 0}));
  expect_rejected(
      far, [&] { far.set_radius(out, 0.01f); }, "cannot resolve radius");

  for (const auto& call : std::vector<std::function<void()>>{
           [&] {
             world.set_position(gone, {0, 0, 0});
           },
           [&] {
             world.set_velocity(gone, {0, 0, 0});
           },
           [&] {
             world.set_angular_velocity(gone, {0, 0, 0});
           },
           [&] {
             world.apply_impulse(gone, {1, 0, 0});
           },
           [&] {
             world.apply_impulse_at(gone, {1, 0, 0}, {0, 0, 0});
           },
           [&] {
             world.apply_force(gone, {1, 0, 0});
           },
           [&] {
             world.apply_torque(gone, {1, 0, 0});
           },
           [&] { world.set_restitution(gone, 0.1f); },
           [&] { world.set_friction(gone, 0.1f); },
           [&] { world.set_mass(gone, 1.0f); },
           [&] { world.set_radius(gone, 0.1f); },
           [&] { world.set_gravity_scale(gone, 0.0f); },
           [&] { world.set_user_data(gone, 7); },
           [&] { (void)world.user_data(gone); },
           [&] { world.set_collision_filter(gone, {}); },
           [&] { (void)world.collision_filter(gone); },
       })
    expect_rejected(world, call, "stale");
}

TEST_CASE("Without rotation a spin or torque is refused, zero is accepted", "[control][invalid]") {
  World world(settings_with({0, -9.81f, 0}, /*rotation=*/false));
  const SphereId id = world.add_sphere(ball({0, 1, 0}));
  expect_rejected(
      world,
      [&] {
        world.set_angular_velocity(id, {0, 1, 0});
      },
      "WorldSettings::rotation");
  expect_rejected(
      world,
      [&] {
        world.apply_torque(id, {0, 1, 0});
      },
      "WorldSettings::rotation");
  world.set_angular_velocity(id, {0, 0, 0});
  world.apply_torque(id, {0, 0, 0});
  CHECK(world.angular_velocity(id) == Vec3::Zero());
}

TEST_CASE("Batch forms set every entry, or refuse all of them with the world unchanged", "[control][invalid]") {
  World world(settings_with({0, 0, 0}));
  std::vector<SphereId> ids;
  for (int k = 0; k < 4; ++k) ids.push_back(world.add_sphere(ball({2.0f * float(k), 0, 0}, 2.0f)));
  const std::vector<Vec3> places{{0, 10, 0}, {2, 10, 0}, {4, 10, 0}, {6, 10, 0}};
  world.set_positions(ids, places);
  world.set_velocities(ids, std::vector<Vec3>(4, Vec3(1, 0, 0)));
  world.apply_impulses(ids, std::vector<Vec3>(4, Vec3(0, 2, 0)));
  for (int k = 0; k < 4; ++k) {
    CHECK(world.position(ids[k]) == places[k]);
    CHECK(world.velocity(ids[k]) == Vec3(1, 1, 0));
  }
  // The same handle twice: both impulses count.
  const std::vector<SphereId> twice{ids[0], ids[0]};
  world.apply_impulses(twice, std::vector<Vec3>(2, Vec3(2, 0, 0)));
  CHECK(world.velocity(ids[0]) == Vec3(3, 1, 0));

  expect_rejected(
      world, [&] { world.set_positions(ids, std::span(places).first(3)); }, "4 handles but 3 values");
  expect_rejected(
      world, [&] { world.apply_impulses(ids, std::vector<Vec3>(5)); }, "4 handles but 5 values");
  std::vector<Vec3> bad = places;
  bad[2] = {kNaN, 0, 0};
  expect_rejected(world, [&] { world.set_positions(ids, bad); }, {"entry 2", "finite"});
  expect_rejected(world,
                  [&] {
                    world.set_velocities(ids, std::vector<Vec3>{{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {9e6f, 0, 0}});
                  },
                  {"entry 3", "kMaxSphereSpeed"});
  std::vector<SphereId> stale = ids;
  const SphereId removed = world.add_sphere(ball({50, 0, 0}));
  REQUIRE(world.remove_sphere(removed));
  stale[1] = removed;
  expect_rejected(world, [&] { world.apply_impulses(stale, std::vector<Vec3>(4, Vec3(1, 0, 0))); },
                  {"entry 1", "stale"});
  // Each impulse alone is within the limit, their sum on one sphere is not: all are put back.
  const std::vector<SphereId> over{ids[1], ids[0], ids[0]};
  expect_rejected(world, [&] { world.apply_impulses(over, std::vector<Vec3>(3, Vec3(1.5e6f, 0, 0))); },
                  {"entry 2", "kMaxSphereSpeed"});
  CHECK(world.velocity(ids[1]) == Vec3(1, 1, 0));
}

TEST_CASE("handles() maps every dense slot to its sphere's handle", "[control]") {
  World world(settings_with({0, -9.81f, 0}));
  std::vector<SphereId> ids;
  for (int k = 0; k < 20; ++k) ids.push_back(world.add_sphere(ball({float(k), 0, 0})));
  world.remove_sphere(ids[3]);
  ids.erase(ids.begin() + 3);
  const std::span<const SphereId> handles = world.handles();
  REQUIRE(handles.size() == world.sphere_count());
  for (std::size_t slot = 0; slot < handles.size(); ++slot) CHECK(handles[slot] == world.id_at(slot));
  for (const SphereId id : ids) CHECK(handles[static_cast<std::size_t>(world.slot_of(id))] == id);
}

TEST_CASE("User data, filters, gravity scales and forces follow their spheres through the Morton re-sort and removals",
          "[control]") {
  WorldSettings settings = settings_with({0, -9.81f, 0});
  settings.reorder_interval = 4;
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  std::vector<SphereId> ids;
  for (int k = 0; k < 300; ++k) {
    ids.push_back(world.add_sphere(ball({u(rng), 1.0f + 0.1f * float(k), u(rng)}, 1.0f, 0.4f)));
    world.set_user_data(ids.back(), 0x1000'0000'0000ull + std::uint64_t(k));
    world.set_collision_filter(ids.back(), {1u << (k % 32), ~std::uint32_t(k)});
  }
  const SphereId floater = ids[5];
  world.set_gravity_scale(floater, 0.0f);
  world.set_position(floater, {100, 50, 100});  // far from the rest: it only floats
  std::vector<std::int64_t> first_slots;
  for (const SphereId id : ids) first_slots.push_back(world.slot_of(id));
  for (int k = 0; k < 20; ++k) world.step(1.0f / 60.0f);  // five re-sorts
  std::size_t moved = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    moved += world.slot_of(ids[k]) != first_slots[k] ? 1 : 0;
    CHECK(world.user_data(ids[k]) == 0x1000'0000'0000ull + k);
    CHECK(world.collision_filter(ids[k]) == CollisionFilter{1u << (k % 32), ~std::uint32_t(k)});
  }
  CHECK(moved > 100);  // the re-sort did move them
  CHECK(world.position(floater) == Vec3(100, 50, 100));

  // Removals swap the last sphere into the hole: the others keep their data.
  for (std::size_t k = 0; k < ids.size(); k += 3) {
    if (ids[k] == floater) continue;
    REQUIRE(world.remove_sphere(ids[k]));
  }
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (k % 3 == 0 && ids[k] != floater) continue;
    CHECK(world.user_data(ids[k]) == 0x1000'0000'0000ull + k);
    CHECK(world.collision_filter(ids[k]) == CollisionFilter{1u << (k % 32), ~std::uint32_t(k)});
  }
  CHECK(world.soa().gravity_scale[static_cast<std::size_t>(world.slot_of(floater))] == 0.0f);

  // A force applied just before a step that begins with a re-sort (step 20 of interval 4)
  // pushes its own sphere after the slots moved.
  constexpr float kStep = 1.0f / 60.0f;
  world.apply_force(floater, {0, 0, 6.0f});
  world.step(kStep);
  const float pushed = 6.0f * (1.0f * kStep);  // F (inv_mass dt), inv_mass 1
  CHECK(world.velocity(floater) == Vec3(0, 0, pushed));
  // Semi-implicit Euler moves with the end velocity; the uniform-acceleration integrator with
  // the mean of the step's start and end (the force's uniform acceleration).
  const float moved_by =
      world.settings().integrator == Integrator::SemiImplicitEuler ? pushed * kStep : 0.5f * pushed * kStep;
  CHECK(world.position(floater).x() == 100.0f);
  CHECK(world.position(floater).y() == 50.0f);
  CHECK(world.position(floater).z() == Approx(100 + moved_by).epsilon(1e-7));
}

namespace {

/// Without the Morton re-sort, so that the spheres keep the slots they were added in.
WorldSettings unsorted() {
  WorldSettings s = settings_with({0, -9.81f, 0});
  s.reorder_interval = 0;
  s.sleep = false;  // the settled pile's contacts are the subject: asleep, it would have none
  return s;
}

/// A two-sphere pile on a floor: `lower` on the floor, `upper` resting on it, settled.
struct Pile {
  World world{unsorted()};
  SphereId lower, upper;
  explicit Pile(bool upper_first) {
    world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.0f});
    const SphereDesc below{.position = {0, 0.5f, 0}, .restitution = 0.0f};
    const SphereDesc above{.position = {0, 1.5f, 0}, .restitution = 0.0f};
    if (upper_first) {
      upper = world.add_sphere(above);
      lower = world.add_sphere(below);
    } else {
      lower = world.add_sphere(below);
      upper = world.add_sphere(above);
    }
    for (int k = 0; k < 120; ++k) world.step(kDt);
  }
};

}  // namespace

TEST_CASE("A teleported sphere gets no warm-start impulse from where it used to be", "[control][warmstart]") {
  for (const bool upper_first : {false, true}) {  // the pair remembered under either sphere's slot
    INFO("upper sphere added first: " << upper_first);
    {
      Pile pile(upper_first);
      REQUIRE(pile.world.last_step_stats().warm_started == 2);  // floor-lower, lower-upper
      // Beside the lower sphere, touching it and the floor: the pair lower-upper is found
      // again, but its remembered impulse held the upper sphere up, along another normal.
      const Vec3 lower = pile.world.position(pile.lower);
      pile.world.set_position(pile.upper, lower + Vec3(1.0f, 0, 0));
      pile.world.set_velocity(pile.upper, Vec3::Zero());
      pile.world.step(kDt);
      CHECK(pile.world.last_contacts().size() == 3);          // floor-lower, floor-upper, lower-upper
      CHECK(pile.world.last_step_stats().warm_started == 1);  // floor-lower alone
    }
    {
      // Into the air: it falls freely, with exactly gravity's velocity.
      Pile pile(upper_first);
      pile.world.set_position(pile.upper, {0, 20, 0});
      pile.world.set_velocity(pile.upper, Vec3::Zero());
      pile.world.step(kDt);
      CHECK(pile.world.velocity(pile.upper) == Vec3(0, -9.81f * kDt, 0));
      CHECK(pile.world.last_step_stats().warm_started == 1);
    }
  }
}

namespace {

/// A falling cloud driven by every kind of call, on `threads` threads.
std::uint64_t driven_cloud(int threads) {
  WorldSettings settings = settings_with({0, -9.81f, 0}, true, threads);
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<SphereId> ids;
  for (int k = 0; k < 1500; ++k)
    ids.push_back(world.add_sphere(ball({8.0f * u(rng), 4.0f + 3.0f * u(rng), 8.0f * u(rng)}, 1.0f, 0.3f)));
  std::vector<Vec3> kicks(ids.size()), places(ids.size() / 10);
  for (int step = 0; step < 120; ++step) {
    for (Vec3& kick : kicks) kick = {0.2f * u(rng), 0.5f * u(rng), 0.2f * u(rng)};
    world.apply_impulses(ids, kicks);
    for (std::size_t k = 0; k < ids.size(); k += 7) world.apply_force(ids[k], {u(rng), 5.0f * u(rng), u(rng)});
    for (std::size_t k = 3; k < ids.size(); k += 11) world.apply_torque(ids[k], {u(rng), u(rng), u(rng)});
    for (std::size_t k = 0; k < ids.size(); k += 13)
      world.apply_impulse_at(ids[k], {u(rng), u(rng), u(rng)}, world.position(ids[k]) + Vec3(0.3f, 0, 0));
    if (step % 30 == 0) {
      for (Vec3& p : places) p = {8.0f * u(rng), 6.0f + u(rng), 8.0f * u(rng)};
      world.set_positions(std::span(ids).first(places.size()), places);
      world.set_gravity_scale(ids[step], 0.5f);
    }
    world.step(1.0f / 60.0f);
  }
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("Driven spheres step bitwise the same on 1 and 3 threads", "[control][determinism][threads]") {
  CHECK(driven_cloud(1) == driven_cloud(3));
}
