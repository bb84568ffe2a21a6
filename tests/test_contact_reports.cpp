// What a step reports of its contacts and impacts for sounds and gameplay (World::last_contacts,
// World::last_impacts): the bounce of the collision passes (Contact::bounce_impulse), the
// resting impulse (Contact::normal_impulse), and the impacts resolved at their exact time
// outside the solve (planes met within a step, continuous collision), against their formulas.
//
// Tolerances: a bounce is checked twice. Against the step's own closing speed (the velocity
// before the step plus g dt, what the collision pass sees) it must agree to float rounding
// (relative 1e-5). Against the analytic speed of a fall from height h, sqrt(2 g h), it may differ
// by what one step's gravity adds, g dt: the step in which the sphere meets the ground applies
// the bounce to the velocity predicted for the end of that step, which lies within g dt of the
// speed at the instant of touching (semi-implicit Euler's velocity is exact at step ends).

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/terrain/terrain_parts.h"

using namespace hail;

namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr float kG = 9.81f;

/// Normal impulse on slot `slot` from this step's contacts and impacts with static geometry.
struct GroundImpulses {
  float bounce = 0, resting = 0, impacts = 0;
};
GroundImpulses ground_impulses(const World& world, std::uint32_t slot) {
  GroundImpulses sum;
  for (const Contact& c : world.last_contacts())
    if (c.a == slot && c.b == kStaticBody) sum.bounce += c.bounce_impulse, sum.resting += c.normal_impulse;
  for (const Impact& i : world.last_impacts())
    if (i.a == slot && i.b == kStaticBody) sum.impacts += i.impulse;
  return sum;
}

}  // namespace

TEST_CASE("A sphere dropped onto a plane reports its bounce as an impact, then rests with m g dt",
          "[contacts][impacts]") {
  // Planes make contacts only for touching spheres: a falling sphere meets the plane inside a
  // step, where the integrator bounces it at the exact time of impact (an Impact).
  const float m = 2.0f, e = 0.5f, h = 5.0f, r = 0.5f;
  World world({.threads = 1, .sleep = false});  // the resting impulse is the subject: asleep, none
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = e, .friction = 0.5f});
  const SphereId id =
      world.add_sphere({.position = {0, h + r, 0}, .radius = r, .mass = m, .restitution = e, .friction = 0.5f});
  int first_impact_step = -1;
  for (int step = 0; step < 120 && first_impact_step < 0; ++step) {
    const float vy_before = world.velocity(id).y();
    world.step(kDt);
    if (world.last_impacts().empty()) continue;
    first_impact_step = step;
    REQUIRE(world.last_impacts().size() == 1);
    const Impact& hit = world.last_impacts()[0];
    CHECK(hit.a == static_cast<std::uint32_t>(world.slot_of(id)));
    CHECK(hit.b == kStaticBody);
    CHECK(hit.feature == (kPlaneFeature | 0u));
    CHECK(hit.ny == -1.0f);  // from the sphere into the plane
    CHECK(hit.time > 0.0f);
    CHECK(hit.time <= kDt);
    CHECK(hit.py == Approx(0.0f).margin(1e-4));  // the contact point lies on the plane
    // The speed it meets the plane with, and its velocity at the end of the step after it
    // rebounds with e. Semi-implicit Euler moves with the velocity after predict all step; the
    // uniform-acceleration integrator meets the plane at the exact time, falling faster by g t
    // than when the step began, and gravity slows the rebound for the rest of the step.
    const bool euler = world.settings().integrator == Integrator::SemiImplicitEuler;
    const float closing = euler ? -(vy_before - kG * kDt) : -vy_before + kG * hit.time;
    const float rebound = euler ? e * closing : e * closing - kG * (kDt - hit.time);
    CHECK(hit.impulse == Approx(m * (1.0f + e) * closing).epsilon(1e-5));
    CHECK(hit.impulse == Approx(m * (1.0f + e) * std::sqrt(2.0f * kG * h)).margin(m * (1.0f + e) * kG * kDt));
    if (!euler) CHECK(hit.impulse == Approx(m * (1.0f + e) * std::sqrt(2.0f * kG * h)).epsilon(1e-4));  // exact
    CHECK(world.velocity(id).y() == Approx(rebound).epsilon(1e-5));
    for (const Contact& c : world.last_contacts()) CHECK(c.bounce_impulse == 0.0f);
  }
  REQUIRE(first_impact_step > 0);
  // Settled (e = 0.5: apexes shrink by e^2 per bounce; 10 s leave it resting): every step the
  // plane takes out the g dt the sphere gained, m g dt, through its touching contact's resting
  // impulse (here: every step), or through an impact below the restitution threshold had it
  // ended a step a hair above the plane; the sum covers both. No bounce.
  for (int step = 0; step < 600; ++step) world.step(kDt);
  for (int step = 0; step < 30; ++step) {
    world.step(kDt);
    const GroundImpulses g = ground_impulses(world, static_cast<std::uint32_t>(world.slot_of(id)));
    INFO("step " << step << ": resting " << g.resting << ", impacts " << g.impacts);
    CHECK(g.bounce == 0.0f);
    CHECK(g.resting + g.impacts == Approx(m * kG * kDt).epsilon(1e-5));
  }
}

TEST_CASE("A sphere dropped onto flat terrain reports the bounce and then the resting impulse in its contacts",
          "[contacts][terrain]") {
  // Terrain contacts are speculative: the step in which the sphere would pass the surface has a
  // contact whose collision pass bounces it, and that contact keeps the bounce.
  const float m = 2.0f, e = 0.5f, h = 5.0f, r = 0.5f;
  auto terrain = std::make_shared<const Terrain>(
      Heightmap::from_function(33, 33, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -16.0f, .origin_z = -16.0f},
                               [](float, float) { return 0.0f; }));
  World world({.threads = 1, .sleep = false});  // the resting impulse is the subject: asleep, none
  world.set_terrain(terrain, e, 0.5f);
  const SphereId id =
      world.add_sphere({.position = {0.3f, h + r, 0.2f}, .radius = r, .mass = m, .restitution = e, .friction = 0.5f});
  int bounces = 0;
  for (int step = 0; step < 120 && bounces == 0; ++step) {
    const float vy_before = world.velocity(id).y(), gap_before = world.position(id).y() - r;
    world.step(kDt);
    CHECK(world.last_impacts().empty());  // nothing fast, no planes
    const GroundImpulses g = ground_impulses(world, static_cast<std::uint32_t>(world.slot_of(id)));
    if (g.bounce == 0.0f) continue;
    ++bounces;
    // What the collision pass sees: the closing speed after predict. Semi-implicit Euler
    // bounces e times it; the uniform-acceleration integrator stops it and gives back e times
    // the approach speed before this step's gravity (solve_collision's gravity_closing).
    const float closing = -(vy_before - kG * kDt);
    const float approach = world.settings().integrator == Integrator::SemiImplicitEuler ? closing : -vy_before;
    CHECK(g.bounce == Approx(m * (closing + e * approach)).epsilon(1e-5));
    CHECK(g.bounce == Approx(m * (1.0f + e) * std::sqrt(2.0f * kG * h)).margin(m * (1.0f + e) * kG * kDt));
    CHECK(g.resting == 0.0f);  // it leaves: nothing to hold
    // The bounce is then moved to its time (kernel/solver/bounce_timing.h): the sphere meets the
    // surface where its path does, at t1, leaves with e times its speed there, and flies on.
    const bool uniform = world.settings().integrator == Integrator::UniformAcceleration;
    const double a = uniform ? kG : 0.0, c0 = uniform ? -vy_before : closing;
    const double t1 = uniform ? (std::sqrt(c0 * c0 + 2.0 * a * gap_before) - c0) / a : gap_before / c0;
    REQUIRE(t1 > 0.0);
    REQUIRE(t1 <= kDt);
    const double after = kDt - t1, leave = e * (c0 + a * t1);
    CHECK(world.velocity(id).y() == Approx(leave - a * after).epsilon(1e-4));
    CHECK(world.position(id).y() - r == Approx(leave * after - 0.5 * a * after * after).margin(1e-5));
    CHECK(world.last_step_stats().timed_bounces == 1);
  }
  REQUIRE(bounces == 1);
  for (int step = 0; step < 600; ++step) world.step(kDt);
  for (int step = 0; step < 30; ++step) {
    world.step(kDt);
    const GroundImpulses g = ground_impulses(world, static_cast<std::uint32_t>(world.slot_of(id)));
    INFO("step " << step << ": resting " << g.resting);
    CHECK(g.bounce == 0.0f);
    // Lying still: the resting passes take exactly the closing speed g dt out of it.
    CHECK(g.resting == Approx(m * kG * kDt).epsilon(1e-5));
    CHECK(g.impacts == 0.0f);
  }
}

TEST_CASE("Two spheres meeting head-on report (1 + e) times the closing speed over the summed inverse masses",
          "[contacts][sphere-sphere]") {
  const float v = 3.0f;
  for (const float m2 : {1.0f, 4.0f}) {
    INFO("m2 = " << m2);
    World world({.gravity = {0, 0, 0}, .threads = 1});
    // 2 cm apart, closing at 2v: a speculative contact that closes within the step.
    const SphereId a = world.add_sphere({.position = {-0.51f, 0, 0},
                                         .velocity = {v, 0, 0},
                                         .radius = 0.5f,
                                         .mass = 1.0f,
                                         .restitution = 1.0f,
                                         .friction = 0.3f});
    const SphereId b = world.add_sphere({.position = {0.51f, 0, 0},
                                         .velocity = {-v, 0, 0},
                                         .radius = 0.5f,
                                         .mass = m2,
                                         .restitution = 1.0f,
                                         .friction = 0.3f});
    world.step(kDt);
    REQUIRE(world.last_contacts().size() == 1);
    const Contact& c = world.last_contacts()[0];
    CHECK(world.id_at(c.a) == a);
    CHECK(world.id_at(c.b) == b);
    const float expected = 2.0f * (2.0f * v) / (1.0f + 1.0f / m2);
    CHECK(c.bounce_impulse == Approx(expected).epsilon(1e-6));
    CHECK(c.normal_impulse == 0.0f);  // they part: no resting impulse
    CHECK(world.last_impacts().empty());
    // The bounce is what moved them: a's change of momentum.
    CHECK(1.0f * (v - world.velocity(a).x()) == Approx(c.bounce_impulse).epsilon(1e-5));
  }
}

TEST_CASE("Continuous collision reports its impacts: a 1,000 m/s sphere on terrain, two crossing spheres",
          "[impacts][ccd]") {
  const float e = 0.5f;
  SECTION("against terrain") {
    auto terrain = std::make_shared<const Terrain>(
        Heightmap::from_function(33, 33, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -16.0f, .origin_z = -16.0f},
                                 [](float, float) { return 0.0f; }));
    World world({.threads = 1});
    world.set_terrain(terrain, e, 0.5f);
    const float speed = 1000.0f, r = 0.1f, m = 3.0f;
    world.add_sphere(
        {.position = {0.3f, 10.0f, 0.2f}, .velocity = {0, -speed, 0}, .radius = r, .mass = m, .restitution = e});
    world.step(kDt);
    REQUIRE(world.last_step_stats().sweep.events >= 1);
    REQUIRE(world.last_impacts().size() == 1);
    const Impact& hit = world.last_impacts()[0];
    CHECK(hit.a == 0);
    CHECK(hit.b == kStaticBody);
    CHECK(hit.feature < terrain->triangles().size());
    CHECK(hit.ny == Approx(-1.0f).margin(1e-6));
    CHECK(hit.py == Approx(0.0f).margin(1e-4));  // the point of impact is on the ground
    // The centre starts 9.9 m above its touching height and moves at speed + g dt.
    const float closing = speed + kG * kDt;
    CHECK(hit.time == Approx((10.0f - r) / closing).epsilon(1e-5));
    CHECK(hit.impulse == Approx(m * (1.0f + e) * closing).epsilon(1e-5));
    for (const Contact& c : world.last_contacts()) CHECK(c.bounce_impulse == 0.0f);  // not a contact's
  }
  SECTION("two spheres") {
    World world({.gravity = {0, 0, 0}, .threads = 1});
    const float v = 2000.0f, r = 0.05f;
    world.add_sphere(
        {.position = {-20.0f, 0, 0}, .velocity = {v, 0, 0}, .radius = r, .mass = 1.0f, .restitution = 1.0f});
    world.add_sphere(
        {.position = {20.0f, 0, 0}, .velocity = {-v, 0, 0}, .radius = r, .mass = 1.0f, .restitution = 1.0f});
    world.step(kDt);
    REQUIRE(world.last_impacts().size() == 1);
    const Impact& hit = world.last_impacts()[0];
    CHECK(hit.b != kStaticBody);
    CHECK(std::min(hit.a, hit.b) == 0);
    CHECK(std::max(hit.a, hit.b) == 1);
    CHECK(hit.time == Approx((40.0f - 2 * r) / (2 * v)).epsilon(1e-5));
    CHECK(hit.px == Approx(0.0f).margin(1e-3));  // they meet in the middle
    CHECK(std::abs(hit.nx) == Approx(1.0f));
    CHECK(hit.impulse == Approx(2.0f * (2.0f * v) / 2.0f).epsilon(1e-5));
  }
}
