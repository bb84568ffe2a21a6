// Every invalid value is rejected with hail::InvalidArgument naming it, and the world is left
// exactly as it was.

#include <cmath>
#include <limits>
#include <string>

#include "catch.h"
#include "hail/features.h"
#include "hail/world.h"
#include "world_refusal.h"

using hail::InvalidArgument;
using hail::PlaneDesc;
using hail::SphereDesc;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;

using namespace hail::testing;

namespace {

/// A small world in motion, so "unchanged" is a real claim.
void populate(World& w) {
  w.add_plane({});
  w.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}});
  w.add_sphere({.position = {2, 3, 0}});
  w.step(1.0f / 60);
}

}  // namespace

TEST_CASE("add_sphere rejects every invalid value and leaves the world unchanged", "[invalid]") {
  World w(WorldSettings{.threads = 1});
  populate(w);
  auto sphere = [](auto edit) {
    SphereDesc d{.position = {0, 5, 0}};
    edit(d);
    return d;
  };
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.position.x() = kNaN; })); }, "position");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.position.y() = kInf; })); }, "position");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.velocity.z() = kNaN; })); }, "velocity");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.angular_velocity.x() = kInf; })); }, "angular_velocity");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.radius = 0; })); }, "radius");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.radius = -1; })); }, "radius");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.radius = kNaN; })); }, "radius");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.mass = 0; })); }, "mass");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.mass = -2; })); }, "mass");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.mass = kInf; })); }, "mass");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.restitution = -0.1f; })); }, "restitution");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.restitution = 1.5f; })); }, "restitution");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.friction = -0.5f; })); }, "friction");
  expect_rejected(
      w, [&] { w.add_sphere(sphere([](SphereDesc& d) { d.friction = kNaN; })); }, "friction");
  // An explicitly static sphere needs no mass.
  const auto before = w.sphere_count();
  w.add_sphere(sphere([](SphereDesc& d) {
    d.mass = 0;
    d.is_static = true;
  }));
  CHECK(w.sphere_count() == before + 1);
}

TEST_CASE("add_plane rejects every invalid value and leaves the world unchanged", "[invalid]") {
  World w(WorldSettings{.threads = 1});
  populate(w);
  expect_rejected(
      w,
      [&] {
        w.add_plane({.normal = {0, 0, 0}});
      },
      "normal");
  expect_rejected(
      w,
      [&] {
        w.add_plane({.normal = {0, kNaN, 0}});
      },
      "normal");
  expect_rejected(
      w, [&] { w.add_plane({.offset = kInf}); }, "offset");
  expect_rejected(
      w, [&] { w.add_plane({.restitution = 2}); }, "restitution");
  expect_rejected(
      w, [&] { w.add_plane({.friction = -1}); }, "friction");
}

TEST_CASE("step rejects dt <= 0 and non-finite dt", "[invalid]") {
  World w(WorldSettings{.threads = 1});
  populate(w);
  for (float dt : {0.0f, -1.0f / 60, kNaN, kInf})
    expect_rejected(
        w, [&] { w.step(dt); }, "dt");
}

TEST_CASE("World settings are validated", "[invalid]") {
  auto rejected = [](WorldSettings s, const std::string& needle) {
    try {
      World w(s);
      FAIL("expected rejection of " << needle);
    } catch (const InvalidArgument& e) {
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  rejected(WorldSettings{.gravity = {0, kNaN, 0}}, "gravity");
  rejected(WorldSettings{.time_scale = -1}, "time_scale");
  rejected(WorldSettings{.time_scale = kInf}, "time_scale");
  rejected(WorldSettings{.threads = -2}, "threads");
  rejected(WorldSettings{.restitution_threshold = -1}, "restitution_threshold");
  auto with = [](auto edit) {
    WorldSettings s;
    edit(s);
    return s;
  };
  rejected(with([](WorldSettings& s) { s.collision_iterations = -1; }), "collision_iterations");
  rejected(with([](WorldSettings& s) { s.resting_iterations = -1; }), "resting_iterations");
  rejected(with([](WorldSettings& s) { s.depenetration_iterations = -1; }), "depenetration_iterations");
  rejected(with([](WorldSettings& s) { s.solver = static_cast<hail::Solver>(7); }), "solver");
  rejected(with([](WorldSettings& s) { s.soft_step.substeps = 0; }), "soft_step.substeps");
  rejected(with([](WorldSettings& s) { s.soft_step.contact_cycles = 0; }), "soft_step.contact_cycles");
  rejected(with([](WorldSettings& s) { s.soft_step.contact_cycles = 0.3f; }), "soft_step.contact_cycles");
  rejected(with([](WorldSettings& s) { s.soft_step.contact_cycles = kNaN; }), "soft_step.contact_cycles");
  rejected(with([](WorldSettings& s) { s.soft_step.damping_ratio = 0; }), "soft_step.damping_ratio");
  rejected(with([](WorldSettings& s) { s.soft_step.damping_ratio = kInf; }), "soft_step.damping_ratio");
  rejected(with([](WorldSettings& s) { s.soft_step.relax_iterations = -1; }), "soft_step.relax_iterations");
  rejected(with([](WorldSettings& s) { s.soft_step.depenetration_iterations_max = -1; }),
           "soft_step.depenetration_iterations_max");
  rejected(with([](WorldSettings& s) { s.soft_step.max_push_speed = -1; }), "soft_step.max_push_speed");
  rejected(with([](WorldSettings& s) { s.depenetration.fraction = 1.5f; }), "depenetration.fraction");
  rejected(with([](WorldSettings& s) { s.depenetration.slop_fraction = kNaN; }), "slop_fraction");
  rejected(with([](WorldSettings& s) { s.speculative_radii = -1; }), "speculative_radii");
  rejected(with([](WorldSettings& s) { s.pair_margin_travel = -1; }), "pair_margin_travel");
  rejected(with([](WorldSettings& s) { s.reorder_interval = -1; }), "reorder_interval");
  rejected(with([](WorldSettings& s) { s.warm_start_factor = 1.5f; }), "warm_start_factor");
  rejected(with([](WorldSettings& s) { s.fast_travel_fraction = 0; }), "fast_travel_fraction");
  rejected(with([](WorldSettings& s) { s.fast_travel_fraction = kNaN; }), "fast_travel_fraction");
  rejected(with([](WorldSettings& s) { s.fast_travel_fraction = 2; }), "fast_travel_fraction");
  rejected(with([](WorldSettings& s) { s.max_sweep_events = 0; }), "max_sweep_events");
  rejected(with([](WorldSettings& s) { s.shock_mass_ratio = 0.5f; }), "shock_mass_ratio");
  rejected(with([](WorldSettings& s) { s.shock_mass_ratio = kNaN; }), "shock_mass_ratio");
  rejected(with([](WorldSettings& s) { s.max_substep = 0; }), "max_substep");
  rejected(with([](WorldSettings& s) { s.max_substep = kInf; }), "max_substep");
#if !HAIL_WITH_ROTATION
  rejected(with([](WorldSettings& s) { s.rotation = true; }), "HAIL_WITH_ROTATION=OFF");
#endif
}

TEST_CASE("Without rotation add_sphere refuses a spinning sphere and leaves the world unchanged", "[invalid]") {
  World w(WorldSettings{.threads = 1, .rotation = false});
  populate(w);
  expect_rejected(
      w,
      [&] {
        w.add_sphere({.position = {0, 5, 0}, .angular_velocity = {0, 0, 1}});
      },
      "angular_velocity");
  // A static sphere never moves: what it was given is dropped, as with rotation on.
  const auto before = w.sphere_count();
  w.add_sphere({.position = {0, 5, 0}, .angular_velocity = {0, 0, 1}, .is_static = true});
  CHECK(w.sphere_count() == before + 1);
}

TEST_CASE("A stale handle is reported, not dereferenced", "[invalid]") {
  World w(WorldSettings{.threads = 1});
  const auto id = w.add_sphere({});
  REQUIRE(w.remove_sphere(id));
  CHECK_FALSE(w.remove_sphere(id));
  CHECK_THROWS_AS(w.position(id), InvalidArgument);
}

TEST_CASE("time_scale 0 freezes the world; time_scale slows it", "[settings]") {
  World frozen(WorldSettings{.time_scale = 0, .threads = 1});
  const auto a = frozen.add_sphere({.position = {0, 5, 0}, .velocity = {1, 0, 0}});
  frozen.step(1.0f / 60);
  CHECK(frozen.position(a) == Vec3(0, 5, 0));
  World slow(WorldSettings{.gravity = Vec3::Zero(), .time_scale = 0.5f, .threads = 1});
  const auto b = slow.add_sphere({.position = {0, 5, 0}, .velocity = {1, 0, 0}});
  for (int k = 0; k < 60; ++k) slow.step(1.0f / 60);
  CHECK(slow.position(b).x() == Approx(0.5).epsilon(1e-4));
}
