// Every invalid value is rejected with hail::InvalidArgument naming it, and the world is left
// exactly as it was.

#include <cmath>
#include <limits>
#include <string>

#include "catch.h"
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

/// The World constructor must refuse `s` with an InvalidArgument naming `needle`.
void settings_rejected(const WorldSettings& s, const std::string& needle) {
  try {
    World w(s);
    FAIL("expected rejection of " << needle);
  } catch (const InvalidArgument& e) {
    INFO("message: " << e.what());
    CHECK(std::string(e.what()).find(needle) != std::string::npos);
  }
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

TEST_CASE("A step too short to move anything is refused, the world unchanged", "[invalid][limits]") {
  // dt 1e-39 (or time_scale 1e-37 at 1/60) passed as "finite and > 0" and turned every sphere NaN.
  World w(WorldSettings{.threads = 1});
  populate(w);
  expect_rejected(w, [&] { w.step(1e-39f); }, {"kMinStep", "1e-39"});
  expect_rejected(
      w, [&] { w.step(1e-10f); }, "kMinStep");
  World slow(WorldSettings{.time_scale = 1e-37f, .threads = 1});  // 1/60 s is too short after the time scale
  slow.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}});
  expect_rejected(slow, [&] { slow.step(1.0f / 60); }, {"kMinStep", "time_scale"});
  CHECK_THROWS_AS(hail::check_step(WorldSettings{}, 1e-40f), InvalidArgument);
  settings_rejected(WorldSettings{.max_substep = 1e-12f}, "max_substep");
  // Paused (time scale 0) steps stay accepted, and the shortest step moves and stays finite,
  // with either solver and the most soft-step substeps.
  World paused(WorldSettings{.time_scale = 0.0f, .threads = 1});
  populate(paused);
  for (hail::Solver solver : {hail::Solver::Passes, hail::Solver::SoftStep}) {
    WorldSettings s{.threads = 1, .solver = solver};
    s.soft_step.substeps = hail::kMaxIterations;
    World w2(s);
    w2.add_plane({});
    w2.add_sphere({.position = {0, 0.5f, 0}, .mass = 1e12f});
    w2.add_sphere({.position = {0, 1.5f, 0}, .mass = 1e-12f});
    for (int k = 0; k < 5; ++k) w2.step(hail::kMinStep);
    CHECK(w2.nan_count() == 0);
    CHECK(std::isfinite(w2.kinetic_energy()));
  }
}

TEST_CASE("Forces, torques and gravity are bounded so one step stays within the speed limits", "[invalid][limits]") {
  // apply_force(3e38) left 2.5e35 m/s after one step, then NaN.
  World w(WorldSettings{.threads = 1});
  populate(w);
  const hail::SphereId id = w.id_at(0);
  expect_rejected(w, [&] { w.apply_force(id, {3e38f, 0, 0}); }, {"accumulated force", "kMaxSphereSpeed"});
  expect_rejected(w, [&] { w.apply_torque(id, {0, 3e38f, 0}); }, {"accumulated torque", "spin"});
  // At the defaults the longest step is 256 * 0.05 = 12.8 s: a 1 kg sphere takes up to
  // 1e6 / 12.8 = 78,125 N.
  w.apply_force(id, {78000.0f, 0, 0});
  expect_rejected(
      w,
      [&] {
        w.apply_force(id, {1000.0f, 0, 0});
      },
      "accumulated force");  // the sum is checked
  w.step(1.0f / 60);
  CHECK(w.nan_count() == 0);
  expect_rejected(w, [&] { w.set_gravity_scale(id, 1e5f); }, {"gravity scale", "kMaxSphereSpeed"});
  w.set_gravity_scale(id, 7000.0f);  // 9.81 * 7000 * 12.8 = 8.8e5 m/s
  settings_rejected(WorldSettings{.gravity = {0, -1e6f, 0}}, "gravity");
  settings_rejected(WorldSettings{.gravity = {0, -3e38f, 0}}, "gravity");
  // A world of shorter longest steps may take stronger gravity.
  World strong(WorldSettings{.gravity = {0, -1e6f, 0}, .max_substep = 0.01f, .max_substeps = 10, .threads = 1});
  populate(strong);
  CHECK(strong.nan_count() == 0);
}

TEST_CASE("Iteration counts have one range wherever they come from", "[invalid][limits]") {
  // 2147483647 resting passes were accepted (8 spheres, 2 steps took over 20 s).
  for (int bad : {-1, hail::kMaxIterations + 1, 2147483647}) {
    INFO(bad);
    settings_rejected(WorldSettings{.resting_iterations = bad}, "resting_iterations");
    settings_rejected(WorldSettings{.collision_iterations = bad}, "collision_iterations");
    settings_rejected(WorldSettings{.depenetration_iterations = bad}, "depenetration_iterations");
    WorldSettings soft;
    soft.soft_step.substeps = bad;
    settings_rejected(soft, "soft_step.substeps");
    soft = {};
    soft.soft_step.relax_iterations = bad;
    settings_rejected(soft, "soft_step.relax_iterations");
    soft = {};
    soft.soft_step.depenetration_iterations_max = bad;
    settings_rejected(soft, "depenetration_iterations_max");
  }
  settings_rejected(WorldSettings{.max_substeps = hail::kMaxSubstepsCap + 1}, "max_substeps");
  World at_most(WorldSettings{.threads = 1, .resting_iterations = hail::kMaxIterations});
  CHECK(at_most.settings().resting_iterations == hail::kMaxIterations);
}
