// Sleeping (WorldSettings::sleep, kernel/world/sleep_islands.h): a settled pile falls asleep
// and stays exactly still; each wake rule (a moving sphere's contact, a swept sphere's impact,
// every control call, removing a sphere, changes of the ground); islands wake whole and only
// themselves; events; the same state on 1 and 2 threads; snapshots keep sleep exactly.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "simd_paths.h"

using namespace hail;

namespace {

constexpr float kDt = 1.0f / 60.0f;

WorldSettings sleepy(int threads = 1) {
  WorldSettings s;
  s.sleep = true;
  s.threads = threads;
  return s;
}

/// A column of three spheres on the ground plane (one island) and a lone sphere far from it.
struct Scene {
  std::vector<SphereId> column;
  SphereId loner;
};

Scene add_column_and_loner(World& world) {
  world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
  Scene scene;
  for (int k = 0; k < 3; ++k)
    scene.column.push_back(world.add_sphere({.position = {0.0f, 0.5f + 1.0f * static_cast<float>(k), 0.0f}}));
  scene.loner = world.add_sphere({.position = {10.0f, 0.5f, 0.0f}});
  return scene;
}

/// Steps until every movable sphere sleeps (at most `steps`); returns the steps taken.
int settle(World& world, int steps = 600) {
  const auto inv_mass = world.spheres().inv_mass;
  const auto movable =
      static_cast<std::size_t>(std::count_if(inv_mass.begin(), inv_mass.end(), [](float m) { return m > 0.0f; }));
  for (int k = 0; k < steps; ++k) {
    world.step(kDt);
    if (world.last_step_stats().sleeping == movable) return k;
  }
  return steps;
}

bool all_sleeping(const World& world, const std::vector<SphereId>& ids) {
  return std::all_of(ids.begin(), ids.end(), [&](SphereId id) { return world.is_sleeping(id); });
}
bool none_sleeping(const World& world, const std::vector<SphereId>& ids) {
  return std::none_of(ids.begin(), ids.end(), [&](SphereId id) { return world.is_sleeping(id); });
}

/// A box of planes with `n` spheres dropped into it in a loose lattice, `row` to a row.
void add_pile(World& world, int n, int row = 6) {
  const float half = 0.55f * static_cast<float>(row) + 0.7f;
  world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
  world.add_plane({.normal = {1, 0, 0}, .offset = -half});
  world.add_plane({.normal = {-1, 0, 0}, .offset = -half});
  world.add_plane({.normal = {0, 0, 1}, .offset = -half});
  world.add_plane({.normal = {0, 0, -1}, .offset = -half});
  const float start = -0.55f * static_cast<float>(row) + 0.3f;
  for (int k = 0; k < n; ++k) {
    const float x = start + 1.1f * static_cast<float>(k % row) + 0.01f * static_cast<float>(k % 7);
    const float z = start + 1.1f * static_cast<float>((k / row) % row);
    const float y = 0.6f + 1.1f * static_cast<float>(k / (row * row));
    world.add_sphere({.position = {x, y, z}, .velocity = {0.3f * static_cast<float>(k % 3 - 1), 0, 0}});
  }
}

}  // namespace

TEST_CASE("A settled column and a lone sphere fall asleep, zeroed, and then stay exactly still", "[sleep]") {
  World world(sleepy());
  const Scene scene = add_column_and_loner(world);
  const int steps = settle(world);
  REQUIRE(steps < 600);
  CHECK(world.last_step_stats().sleeping == 4);
  CHECK(all_sleeping(world, scene.column));
  CHECK(world.is_sleeping(scene.loner));
  const std::uint64_t hash = world.state_hash();
  for (int k = 0; k < 120; ++k) world.step(kDt);
  CHECK(world.state_hash() == hash);  // positions and velocities bitwise the same: nothing moved
  CHECK(world.velocity(scene.loner) == Vec3::Zero());
  CHECK(world.last_contacts().empty());  // sleepers cost no contact
  CHECK(world.sleep_events().empty());   // they fell asleep long ago
}

TEST_CASE("Sleep events list the spheres that fell asleep, by handle index, once", "[sleep]") {
  World world(sleepy());
  add_column_and_loner(world);
  std::vector<std::uint32_t> slept;
  for (int k = 0; k < 600 && slept.size() < 4; ++k) {
    world.step(kDt);
    for (SphereId id : world.sleep_events()) slept.push_back(id.index);
    CHECK(std::is_sorted(world.sleep_events().begin(), world.sleep_events().end(),
                         [](SphereId a, SphereId b) { return a.index < b.index; }));
  }
  std::sort(slept.begin(), slept.end());
  CHECK(slept == std::vector<std::uint32_t>{0, 1, 2, 3});
}

TEST_CASE("With sleeping off nothing sleeps", "[sleep]") {
  WorldSettings settings = sleepy();
  settings.sleep = false;
  World world(settings);
  const Scene scene = add_column_and_loner(world);
  for (int k = 0; k < 200; ++k) world.step(kDt);
  CHECK(none_sleeping(world, scene.column));
  CHECK(!world.is_sleeping(scene.loner));
  CHECK(world.last_step_stats().sleeping == 0);
  CHECK(world.sleep_events().empty());
}

TEST_CASE("Every control call wakes the sphere's island and no other", "[sleep]") {
  using Call = std::function<void(World&, SphereId)>;
  const std::vector<std::pair<std::string, Call>> calls = {
      {"set_position", [](World& w, SphereId id) { w.set_position(id, w.position(id) + Vec3(0, 0.001f, 0)); }},
      {"set_velocity",
       [](World& w, SphereId id) {
         w.set_velocity(id, {0.1f, 0, 0});
       }},
      {"set_angular_velocity",
       [](World& w, SphereId id) {
         w.set_angular_velocity(id, {0, 1, 0});
       }},
      {"apply_impulse",
       [](World& w, SphereId id) {
         w.apply_impulse(id, {0.1f, 0, 0});
       }},
      {"apply_impulse_at",
       [](World& w, SphereId id) {
         w.apply_impulse_at(id, {0.1f, 0, 0}, w.position(id));
       }},
      {"apply_force",
       [](World& w, SphereId id) {
         w.apply_force(id, {1, 0, 0});
       }},
      {"apply_torque",
       [](World& w, SphereId id) {
         w.apply_torque(id, {0, 1, 0});
       }},
      {"set_restitution", [](World& w, SphereId id) { w.set_restitution(id, 0.25f); }},
      {"set_friction", [](World& w, SphereId id) { w.set_friction(id, 0.25f); }},
      {"set_mass", [](World& w, SphereId id) { w.set_mass(id, 3.0f); }},
      {"set_radius", [](World& w, SphereId id) { w.set_radius(id, 0.49f); }},
      {"set_gravity_scale", [](World& w, SphereId id) { w.set_gravity_scale(id, 0.5f); }},
      {"set_collision_filter",
       [](World& w, SphereId id) {
         w.set_collision_filter(id, {1, 1});
       }},
      {"set_positions",
       [](World& w, SphereId id) {
         const Vec3 p = w.position(id);
         w.set_positions({&id, 1}, {&p, 1});
       }},
      {"set_velocities",
       [](World& w, SphereId id) {
         const Vec3 v(0.1f, 0, 0);
         w.set_velocities({&id, 1}, {&v, 1});
       }},
      {"apply_impulses",
       [](World& w, SphereId id) {
         const Vec3 j(0.1f, 0, 0);
         w.apply_impulses({&id, 1}, {&j, 1});
       }},
  };
  World settled(sleepy());
  const Scene scene = add_column_and_loner(settled);
  REQUIRE(settle(settled) < 600);
  std::vector<std::byte> snapshot;
  settled.save(snapshot);
  for (const auto& [name, call] : calls) {
    INFO(name);
    World world(sleepy());
    world.restore(snapshot);
    REQUIRE(all_sleeping(world, scene.column));
    call(world, scene.column[2]);  // the top of the column
    CHECK(none_sleeping(world, scene.column));
    CHECK(world.is_sleeping(scene.loner));
    world.step(kDt);
    CHECK(world.wake_events().size() == 3);  // the call's wakes are the next step's events
  }
}

TEST_CASE("A sphere dropped on a sleeping column wakes it in the step it arrives", "[sleep]") {
  World world(sleepy());
  const Scene scene = add_column_and_loner(world);
  REQUIRE(settle(world) < 600);
  const SphereId dropped = world.add_sphere({.position = {0.0f, 4.0f, 0.0f}, .velocity = {0, -2, 0}});
  bool woke = false;
  for (int k = 0; k < 120 && !woke; ++k) {
    world.step(kDt);
    if (!world.is_sleeping(scene.column[2])) {
      woke = true;
      // The step that woke it solved the contact that did: it did not wait for the next one.
      const std::int64_t a = world.slot_of(dropped), b = world.slot_of(scene.column[2]);
      const auto contacts = world.last_contacts();
      CHECK(std::any_of(contacts.begin(), contacts.end(),
                        [&](const Contact& c) { return (c.a == a && c.b == b) || (c.a == b && c.b == a); }));
      CHECK(none_sleeping(world, scene.column));
      CHECK(world.is_sleeping(scene.loner));
    }
  }
  CHECK(woke);
}

TEST_CASE("A swept sphere's impact on a sleeper wakes it and moves it in that step", "[sleep]") {
  World world(sleepy());
  const Scene scene = add_column_and_loner(world);
  REQUIRE(settle(world) < 600);
  // 120 m/s: 2 m a step, four radii, so it is swept (continuous collision) from 6 m away.
  const SphereId bullet = world.add_sphere({.position = {4.0f, 0.5f, 0.0f}, .velocity = {120, 0, 0}, .mass = 0.1f});
  bool hit = false;
  for (int k = 0; k < 10 && !hit; ++k) {
    world.step(kDt);
    if (!world.is_sleeping(scene.loner)) {
      hit = true;
      CHECK(world.velocity(scene.loner).x() > 0.0f);
      const auto woken = world.wake_events();
      CHECK(std::find(woken.begin(), woken.end(), scene.loner) != woken.end());
    }
  }
  CHECK(hit);
  CHECK(all_sleeping(world, scene.column));
  (void)bullet;
}

TEST_CASE("Removing a sphere wakes its island; removing a static one wakes what rested on it", "[sleep]") {
  World world(sleepy());
  const Scene scene = add_column_and_loner(world);
  const SphereId post = world.add_sphere({.position = {-10.0f, 0.5f, 0.0f}, .is_static = true});
  const SphereId perched = world.add_sphere({.position = {-10.0f, 1.5f, 0.0f}});
  REQUIRE(settle(world) < 600);
  REQUIRE(world.is_sleeping(perched));
  REQUIRE(!world.is_sleeping(post));  // immovable spheres never sleep
  world.remove_sphere(scene.column[0]);
  CHECK(!world.is_sleeping(scene.column[1]));
  CHECK(!world.is_sleeping(scene.column[2]));
  CHECK(world.is_sleeping(scene.loner));
  CHECK(world.is_sleeping(perched));
  world.remove_sphere(post);
  CHECK(!world.is_sleeping(perched));
  CHECK(world.is_sleeping(scene.loner));
  const float y = world.position(perched).y();
  for (int k = 0; k < 10; ++k) world.step(kDt);
  CHECK(world.position(perched).y() < y - 0.1f);  // it falls
}

TEST_CASE("Changing the ground wakes every sleeper", "[sleep]") {
  const std::vector<std::pair<std::string, std::function<void(World&)>>> changes = {
      {"add_plane",
       [](World& w) {
         w.add_plane({.normal = {1, 0, 0}, .offset = -50.0f});
       }},
      {"set_ground_filter",
       [](World& w) {
         w.set_ground_filter({1, kAllCategories});
       }},
      {"shift_origin",
       [](World& w) {
         w.shift_origin({1, 0, 0});
       }},
  };
  for (const auto& [name, change] : changes) {
    INFO(name);
    World world(sleepy());
    const Scene scene = add_column_and_loner(world);
    REQUIRE(settle(world) < 600);
    change(world);
    CHECK(none_sleeping(world, scene.column));
    CHECK(!world.is_sleeping(scene.loner));
  }
}

TEST_CASE("Sleeping settings are checked", "[sleep]") {
  for (float bad : {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    WorldSettings s = sleepy();
    s.sleep_time = bad;
    CHECK_THROWS_AS(World(s), InvalidArgument);
    s = sleepy();
    s.sleep_linear_speed = bad;
    CHECK_THROWS_AS(World(s), InvalidArgument);
    s = sleepy();
    s.sleep_angular_speed = bad;
    CHECK_THROWS_AS(World(s), InvalidArgument);
  }
}

namespace {

/// A sphere pinched between a static sphere below and a heavy one (10 kg) resting on top of it,
/// all three on the vertical through the origin, spinning at `spin` about that line, the line
/// through its two contacts (both carry load: the heavy one's weight and its own).
struct Pinch {
  SphereId spinner, heavy;
};
Pinch add_pinched_spinner(World& world, float spin) {
  world.add_sphere({.position = {0.0f, 0.5f, 0.0f}, .is_static = true});
  const SphereId spinner = world.add_sphere({.position = {0.0f, 1.5f, 0.0f}, .angular_velocity = {0.0f, spin, 0.0f}});
  const SphereId heavy = world.add_sphere({.position = {0.0f, 2.5f, 0.0f}, .mass = 10.0f});
  return {spinner, heavy};
}

/// Contacts of the last step that touch `slot` and carry load (normal impulse > 0).
std::size_t loaded_contacts(const World& world, std::uint32_t slot) {
  const auto contacts = world.last_contacts();
  return static_cast<std::size_t>(std::count_if(contacts.begin(), contacts.end(), [&](const Contact& c) {
    return (c.a == slot || c.b == slot) && c.normal_impulse > 0.0f;
  }));
}

}  // namespace

TEST_CASE("A sphere pinched between two static ones, spinning about the line through the contacts, sleeps", "[sleep]") {
  // The twist slides neither contact, and hail has no torsional resistance: the spin never
  // decays (sleeping off, it is all there after 5 s), yet it moves nothing.
  constexpr float kSpin = 2.0f;  // rad/s, 20 times sleep_angular_speed
  WorldSettings off_settings = sleepy();
  off_settings.sleep = false;
  World off(off_settings);
  const Pinch pinch_off = add_pinched_spinner(off, kSpin);
  for (int k = 0; k < 300; ++k) {
    off.step(kDt);
    REQUIRE(loaded_contacts(off, static_cast<std::uint32_t>(off.slot_of(pinch_off.spinner))) == 2);
  }
  CHECK(off.angular_velocity(pinch_off.spinner).y() == Approx(kSpin).epsilon(1e-3));
  CHECK(off.velocity(pinch_off.spinner).norm() < WorldSettings{}.sleep_linear_speed);
  CHECK(off.position(pinch_off.heavy).x() == 0.0f);  // the column stands
  CHECK(off.position(pinch_off.heavy).z() == 0.0f);

  World on(sleepy());
  const Pinch pinch = add_pinched_spinner(on, kSpin);
  const int steps = settle(on, 300);
  CHECK(steps < 60);  // sleep_time (0.5 s, 30 steps) and a little
  CHECK(on.is_sleeping(pinch.spinner));
  CHECK(on.is_sleeping(pinch.heavy));
  CHECK(on.angular_velocity(pinch.spinner) == Vec3::Zero());
}

TEST_CASE("A sphere that spins about its one loaded contact's normal sleeps; spin across it keeps it awake",
          "[sleep]") {
  for (const bool across : {false, true}) {
    INFO((across ? "across the normal" : "about the normal"));
    World world(sleepy());
    world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f, .friction = 0.0f});  // nothing stops the spin
    const Vec3 spin = across ? Vec3(0.0f, 0.0f, 1.0f) : Vec3(0.0f, 1.0f, 0.0f);
    const SphereId id = world.add_sphere({.position = {0, 0.5f, 0}, .angular_velocity = spin, .friction = 0.0f});
    for (int k = 0; k < 120; ++k) world.step(kDt);
    CHECK(world.is_sleeping(id) == !across);
  }
}

TEST_CASE("A sphere rolling slowly on the ground stays awake while it rolls", "[sleep]") {
  // Slower than sleep_linear_speed, but its spin (0.4 rad/s) slides the ground contact (it is
  // across the normal): counted, it keeps the sphere awake. With no rolling resistance it
  // rolls on for good.
  World world(sleepy());
  world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
  constexpr float kRadius = 0.1f, kSpeed = 0.04f;
  REQUIRE(kSpeed < WorldSettings{}.sleep_linear_speed);
  REQUIRE(kSpeed / kRadius > WorldSettings{}.sleep_angular_speed);
  const SphereId ball = world.add_sphere({.position = {0, kRadius, 0},
                                          .velocity = {kSpeed, 0, 0},
                                          .angular_velocity = {0, 0, -kSpeed / kRadius},
                                          .radius = kRadius});
  for (int k = 0; k < 300; ++k) {  // 5 s, ten times sleep_time
    world.step(kDt);
    REQUIRE(!world.is_sleeping(ball));
  }
  CHECK(world.position(ball).x() == Approx(5.0f * kSpeed).epsilon(0.05));  // it rolled all the while
  CHECK(world.velocity(ball).x() == Approx(kSpeed).epsilon(0.05));
}

TEST_CASE("A pile with sleeping on steps bitwise the same on 1 and 2 threads and every SIMD path", "[sleep][threads]") {
  std::vector<std::uint64_t> hashes;
  std::vector<std::size_t> sleeping;
  for (SimdPath path : hail::testing::supported_paths())
    for (int threads : {1, 2}) {
      hail::testing::ScopedSimdPath scoped(path);
      World world(sleepy(threads));
      add_pile(world, 300);
      std::size_t most_asleep = 0;
      for (int k = 0; k < 700; ++k) {
        world.step(kDt);
        most_asleep = std::max(most_asleep, world.last_step_stats().sleeping);
      }
      hashes.push_back(world.state_hash());
      sleeping.push_back(most_asleep);
    }
  for (std::size_t k = 1; k < hashes.size(); ++k) {
    CHECK(hashes[k] == hashes[0]);
    CHECK(sleeping[k] == sleeping[0]);
  }
  CHECK(sleeping[0] > 0);  // the test saw sleepers
}

TEST_CASE("Islands built in parallel blocks decide the same on 1 and 2 threads", "[sleep][threads]") {
  // 2,500 spheres: two blocks of spheres and several of contacts for the islands phase, whose
  // union-find and per-island flags are shared by the threads (kernel/world/sleep_islands.cpp).
  struct Run {
    std::vector<std::size_t> sleeping, ready;
    std::uint64_t hash = 0;
  };
  std::vector<Run> runs;
  for (int threads : {1, 2}) {
    World world(sleepy(threads));
    add_pile(world, 2500, 20);
    Run run;
    for (int k = 0; k < 500; ++k) {
      world.step(kDt);
      run.sleeping.push_back(world.last_step_stats().sleeping);
      run.ready.push_back(world.last_step_stats().ready_to_sleep);
    }
    run.hash = world.state_hash();
    runs.push_back(run);
  }
  CHECK(runs[1].hash == runs[0].hash);
  CHECK(runs[1].sleeping == runs[0].sleeping);
  CHECK(runs[1].ready == runs[0].ready);
  // The test saw spheres ready to sleep and held awake by their islands, and islands asleep.
  CHECK(std::any_of(runs[0].ready.begin(), runs[0].ready.end(), [](std::size_t n) { return n > 0; }));
  CHECK(*std::max_element(runs[0].sleeping.begin(), runs[0].sleeping.end()) > 0);
}

TEST_CASE("A sphere at rest long enough is counted ready, and held awake by a newer one of its island", "[sleep]") {
  World world(sleepy());
  world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
  const SphereId first = world.add_sphere({.position = {0.0f, 0.5f, 0.0f}});
  for (int k = 0; k < 24; ++k) world.step(kDt);  // 0.4 s at rest: not yet sleep_time (0.5 s)
  CHECK(world.last_step_stats().ready_to_sleep == 0);
  // A second sphere at rest, touching the first: one island, whose newer sphere's timer is short.
  const SphereId second = world.add_sphere({.position = {1.0f, 0.5f, 0.0f}});
  for (int k = 0; k < 12; ++k) world.step(kDt);  // 0.6 s for the first, 0.2 s for the second
  CHECK(world.last_step_stats().ready_to_sleep == 1);
  CHECK(world.last_step_stats().sleeping == 0);
  CHECK(!world.is_sleeping(first));
  for (int k = 0; k < 30; ++k) world.step(kDt);  // the second has rested 0.7 s too
  CHECK(world.is_sleeping(first));
  CHECK(world.is_sleeping(second));
  CHECK(world.last_step_stats().ready_to_sleep == 0);  // counts only awake spheres
}

TEST_CASE("A snapshot with sleepers restores their sleep exactly", "[sleep]") {
  World world(sleepy());
  add_pile(world, 200);
  for (int k = 0; k < 400; ++k) world.step(kDt);
  REQUIRE(world.last_step_stats().sleeping > 0);
  std::vector<std::byte> snapshot;
  world.save(snapshot);
  World copy(sleepy());
  copy.restore(snapshot);
  for (std::size_t i = 0; i < world.sphere_count(); ++i)
    CHECK(copy.is_sleeping(world.id_at(i)) == world.is_sleeping(world.id_at(i)));
  for (int k = 0; k < 200; ++k) world.step(kDt), copy.step(kDt);
  CHECK(copy.state_hash() == world.state_hash());
  CHECK(copy.last_step_stats().sleeping == world.last_step_stats().sleeping);
}

TEST_CASE("Sleepers keep their touches: a column falling asleep ends none", "[sleep][events]") {
  World world(sleepy());
  world.set_events({.touch = true});
  const Scene scene = add_column_and_loner(world);
  // A sphere that drifts forever, touching nothing, keeps the world's steps running.
  const SphereId drifter = world.add_sphere({.position = {-20.0f, 5.0f, 0.0f}, .velocity = {-1, 0, 0}});
  world.set_gravity_scale(drifter, 0.0f);
  std::size_t ended_while_asleep = 0;
  bool slept = false;
  for (int k = 0; k < 600; ++k) {
    world.step(kDt);
    const bool now_asleep = all_sleeping(world, scene.column) && world.is_sleeping(scene.loner);
    if (slept) ended_while_asleep += world.touch_end_events().size();
    slept = slept || now_asleep;
  }
  REQUIRE(slept);
  CHECK(!world.is_sleeping(drifter));
  CHECK(ended_while_asleep == 0);
}

TEST_CASE("A pile woken by a drop has the contacts and warm starts of the same pile never put to sleep", "[sleep]") {
  // The same pile twice, sleeping on and off, stepped alike until the first sleeps whole; then a
  // sphere dropped on each. In the step that wakes the sleeping pile, its contacts must be the
  // awake pile's (the woken spheres predicted, so their speculative contacts are found) and
  // start from the impulses they had when they fell asleep (kept while asleep), or the woken
  // pile sags and answers the drop differently (`hail-bench sleep`, part 2).
  WorldSettings off_settings = sleepy();
  off_settings.sleep = false;
  World on(sleepy()), off(off_settings);
  // 3 x 3 x 4 touching spheres in a box of planes (one island), and inside it a sphere that
  // meets the ground and no sphere (collision filters), frictionless, spinning about a
  // horizontal axis for ever (its spin slides its one contact, so it counts and keeps the
  // sphere awake; a spin about the vertical would not), so that every step has a contact to
  // store while the pile sleeps.
  for (World* w : {&on, &off}) {
    w->add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
    w->add_plane({.normal = {1, 0, 0}, .offset = -1.5f});
    w->add_plane({.normal = {-1, 0, 0}, .offset = -1.5f});
    w->add_plane({.normal = {0, 0, 1}, .offset = -1.5f});
    w->add_plane({.normal = {0, 0, -1}, .offset = -1.5f});
    for (int k = 0; k < 36; ++k)
      w->add_sphere({.position = {static_cast<float>(k % 3 - 1), 0.5f + 1.02f * static_cast<float>(k / 9),
                                  static_cast<float>((k / 3) % 3 - 1) + 0.01f * static_cast<float>(k % 2)}});
    w->set_ground_filter({.category = 4, .mask = kAllCategories});
    w->add_sphere({.position = {0.0f, 0.5f, 0.0f},
                   .angular_velocity = {3, 0, 0},
                   .friction = 0.0f,
                   .filter = {.category = 2, .mask = 4}});
  }
  int settled = 0;
  while (settled < 1200 && on.last_step_stats().sleeping < 36) on.step(kDt), ++settled;
  REQUIRE(settled < 1200);
  for (int k = 0; k < settled; ++k) off.step(kDt);
  for (World* w : {&on, &off}) w->add_sphere({.position = {0.1f, 5.0f, 0.2f}, .velocity = {0, -3, 0}});
  int woke_at = -1;
  for (int k = 0; k < 60 && woke_at < 0; ++k) {
    on.step(kDt);
    off.step(kDt);
    if (on.last_step_stats().sleeping == 0) woke_at = k;
    REQUIRE((woke_at >= 0 || on.last_step_stats().static_contacts > 0));  // the spinner's contact is stored
  }
  REQUIRE(woke_at >= 0);
  const StepStats &a = on.last_step_stats(), &b = off.last_step_stats();
  INFO("on: " << a.static_contacts << " + " << a.sphere_contacts << " warm " << a.warm_started
              << "; off: " << b.static_contacts << " + " << b.sphere_contacts << " warm " << b.warm_started
              << "; woke at " << woke_at << " after settling " << settled);
  // Positions differ a little (the awake pile crept on while the other slept), so a contact at
  // the edge of the speculative margin may be in one and not the other. Without the woken
  // spheres' prediction: 102 contacts against the awake pile's 113; without the sleepers'
  // impulses kept: 1 of 112 warm started (the spinner's).
  const std::size_t contacts = a.static_contacts + a.sphere_contacts;
  CHECK(contacts + 2 >= b.static_contacts + b.sphere_contacts);
  CHECK(10 * a.warm_started >= 9 * contacts);
}
