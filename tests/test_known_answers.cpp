// The cases with a known answer from docs/scenes.md (A bounce, B slide to roll,
// C head-on, D Newton's cradle), checked against their formulas.

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "catch.h"
#include "hail/heightmap.h"
#include "hail/terrain.h"
#include "hail/world.h"

using hail::Integrator;
using hail::PlaneDesc;
using hail::Solver;
using hail::SphereDesc;
using hail::SphereId;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;

namespace {

/// Case A: r = 0.5, m = 1, lowest point dropped from 10 m onto flat ground, e = 0.8, no
/// friction. Returns the first `count` apex heights of the lowest point. The ground is a plane,
/// or with `terrain` a flat heightmap (its contacts speculative; the sphere off its grid lines).
std::vector<double> bounce_apexes(float dt, Integrator integrator, int count, Solver solver = Solver::Passes,
                                  bool terrain = false) {
  WorldSettings settings;
  settings.threads = 1;
  settings.integrator = integrator;
  settings.solver = solver;
  World world(settings);
  if (terrain) {
    world.set_terrain(std::make_shared<const hail::Terrain>(hail::Heightmap::from_function(
                          33, 33, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -16.0f, .origin_z = -16.0f},
                          [](float, float) { return 0.0f; })),
                      0.8f, 0.0f);
  } else {
    world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.8f, .friction = 0});
  }
  const Vec3 start = terrain ? Vec3{0.3f, 10.5f, 0.2f} : Vec3{0, 10.5f, 0};
  const SphereId id =
      world.add_sphere({.position = start, .radius = 0.5f, .mass = 1, .restitution = 0.8f, .friction = 0});
  // An apex is the highest sampled position of a rise (sampling misses the true top by at most
  // g (dt/2)^2 / 2: 0.3 mm at dt = 1/60, far below the tolerances).
  std::vector<double> apexes;
  double highest = -1.0;
  for (int k = 0; k < 20.0 / dt && static_cast<int>(apexes.size()) < count; ++k) {
    world.step(dt);
    const double vy = world.velocity(id).y(), y = world.position(id).y() - 0.5;
    if (vy > 0) highest = std::max(highest, y);
    if (vy <= 0 && highest >= 0) {
      apexes.push_back(std::max(highest, y));
      highest = -1.0;
    }
  }
  return apexes;
}

/// Case D: five spheres r = 0.5, m = 1, e = 1, touching in a row along x at rest in zero
/// gravity, and a striker at `striker_x` moving at 1 m/s towards them.
struct Cradle {
  std::unique_ptr<World> world;
  std::vector<SphereId> row;
  SphereId striker;
  explicit Cradle(float striker_x, Solver solver = Solver::Passes) {
    WorldSettings settings;
    settings.gravity = Vec3::Zero();
    settings.threads = 1;
    settings.solver = solver;
    world = std::make_unique<World>(settings);
    for (int k = 0; k < 5; ++k)
      row.push_back(world->add_sphere(
          {.position = {float(k), 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 1, .friction = 0}));
    striker = world->add_sphere({.position = {striker_x, 0, 0},
                                 .velocity = {1, 0, 0},
                                 .radius = 0.5f,
                                 .mass = 1,
                                 .restitution = 1,
                                 .friction = 0});
  }
};

}  // namespace

TEST_CASE("A: bounce apexes follow 10 e^(2n)", "[known][bounce]") {
  struct Run {
    float dt;
    Integrator integrator;
    double tolerance;
  };
  // At dt = 1/60 only the uniform-acceleration integrator is asked for 0.5%: semi-implicit Euler
  // carries its own O(dt) energy error in free flight (apex +v dt/2: +1.7%, +2.2%, +4.0% here),
  // which no impact treatment can remove. hail-bench accuracy reports both.
  // The soft step (WorldSettings::solver) bounces the same: the impact is the integrator's,
  // at its exact time, and never reaches the solver (hail-bench accuracy: the same error).
  const Run run = GENERATE(Run{1.0f / 1000, Integrator::SemiImplicitEuler, 0.01},
                           Run{1.0f / 1000, Integrator::UniformAcceleration, 0.01},
                           Run{1.0f / 60, Integrator::UniformAcceleration, 0.005});
  const Solver solver = GENERATE(Solver::Passes, Solver::SoftStep);
  const std::vector<double> apexes = bounce_apexes(run.dt, run.integrator, 3, solver);
  REQUIRE(apexes.size() == 3);
  for (int n = 1; n <= 3; ++n) {
    const double exact = 10.0 * std::pow(0.8, 2 * n);
    INFO("dt = " << run.dt << " integrator " << int(run.integrator) << " solver " << int(solver) << " apex " << n
                 << " = " << apexes[n - 1] << ", exact " << exact);
    CHECK(std::abs(apexes[n - 1] - exact) <= run.tolerance * exact);
  }
}

TEST_CASE("A on terrain: a bounce off a speculative contact is as exact as off a plane", "[known][bounce][terrain]") {
  // The collision pass bounces the sphere up to a step's travel above the ground; the bounce is
  // then moved to its time (kernel/solver/bounce_timing.h). Without that the apexes were high by
  // 3.8%, 8.8% and 14.4% at dt 1/60 (docs/accuracy.md). The soft step is not asked: its
  // substeps bring the sphere to the ground before restitution acts (3.7% at 1/60).
  const Integrator integrator = GENERATE(Integrator::UniformAcceleration, Integrator::SemiImplicitEuler);
  const float dt = GENERATE(1.0f / 60, 1.0f / 240);
  const std::vector<double> on_terrain = bounce_apexes(dt, integrator, 3, Solver::Passes, true);
  const std::vector<double> on_plane = bounce_apexes(dt, integrator, 3, Solver::Passes, false);
  REQUIRE(on_terrain.size() == 3);
  REQUIRE(on_plane.size() == 3);
  for (int n = 1; n <= 3; ++n) {
    const double exact = 10.0 * std::pow(0.8, 2 * n);
    INFO("dt = " << dt << " integrator " << int(integrator) << " apex " << n << ": terrain " << on_terrain[n - 1]
                 << ", plane " << on_plane[n - 1] << ", exact " << exact);
    // The same as the plane's to 1e-4 of the apex (the plane's own error: 6e-5 under the
    // uniform integrator, 4% under semi-implicit Euler at 1/60), so within 0.5% under the former.
    CHECK(std::abs(on_terrain[n - 1] - on_plane[n - 1]) <= 1e-4 * exact);
    if (integrator == Integrator::UniformAcceleration) CHECK(std::abs(on_terrain[n - 1] - exact) <= 0.005 * exact);
  }
}

TEST_CASE("Rolling resistance: a rolling sphere slows at 5/7 mu_r g and a slope up to mu_r holds it",
          "[known][friction][rolling]") {
  // The constant-torque model (WorldSettings::rolling_resistance, kernel/solver/rolling_resistance.h):
  // torque mu_r r N against the roll, friction keeping the sphere rolling. On flat ground
  // a = 5/7 mu_r g; on a slope of angle theta a = 5/7 g (sin theta - mu_r cos theta) when
  // tan theta > mu_r, and none below.
  const float mu_r = GENERATE(0.05f, 0.2f);
  const float dt = 1.0f / 60, g = 9.81f;
  auto world_on = [&](const Vec3& normal) {
    WorldSettings settings;
    settings.threads = 1;
    settings.sleep = false;
    settings.rolling_resistance = mu_r;
    auto world = std::make_unique<World>(settings);
    world->add_plane({.normal = normal, .offset = 0, .restitution = 0, .friction = 0.9f});
    return world;
  };
  SECTION("flat ground") {
    auto world = world_on({0, 1, 0});
    const SphereId id = world->add_sphere({.position = {0, 0.5f, 0},
                                           .velocity = {2, 0, 0},
                                           .angular_velocity = {0, 0, -4},
                                           .radius = 0.5f,
                                           .mass = 1,
                                           .restitution = 0,
                                           .friction = 0.9f});
    for (int k = 0; k < 60; ++k) world->step(dt);
    const double expected = 2.0 - 5.0 / 7.0 * mu_r * g * 60 * dt;
    INFO("mu_r " << mu_r << ": v after 1 s " << world->velocity(id).x() << ", expected " << expected);
    CHECK(world->velocity(id).x() == Approx(expected).epsilon(1e-4));
    CHECK(world->angular_velocity(id).z() * -0.5f == Approx(world->velocity(id).x()).epsilon(1e-4));  // still rolling
  }
  SECTION("slopes below and above mu_r") {
    for (const float tan_theta : {0.8f * mu_r, 2.0f * mu_r}) {
      const float theta = std::atan(tan_theta);
      const Vec3 normal(-std::sin(theta), std::cos(theta), 0);  // downhill is +x
      auto world = world_on(normal);
      const SphereId id =
          world->add_sphere({.position = 0.5f * normal, .radius = 0.5f, .mass = 1, .restitution = 0, .friction = 0.9f});
      for (int k = 0; k < 60; ++k) world->step(dt);
      const Vec3 v = world->velocity(id);
      const double speed = v.norm();
      if (tan_theta < mu_r) {
        // Held still: the rolling impulse is warm-started, so the resting passes' friction
        // already holds the sphere (about 5e-10 m/s; before the warm start the sweeps left
        // (5/7)^8 of each step's pull, 4e-4 m/s at mu_r 0.2).
        INFO("tan theta " << tan_theta << ": speed " << speed);
        CHECK(speed < 1e-6);
      } else {
        const double expected = 5.0 / 7.0 * g * (std::sin(theta) - mu_r * std::cos(theta)) * 60 * dt;
        INFO("tan theta " << tan_theta << ": speed " << speed << ", expected " << expected);
        // Exact to float rounding (2e-7 at mu_r 0.2). The sphere must keep its plane contact
        // every step (plane_touching): left a rounding above the plane for one step, it had
        // none, and gained a step of free acceleration (+1.7% at mu_r 0.2 after 1 s).
        CHECK(speed == Approx(expected).epsilon(1e-5));
      }
    }
  }
}

TEST_CASE("Rolling resistance is refused with the soft step, which has none", "[rolling]") {
  WorldSettings settings;
  settings.solver = Solver::SoftStep;
  settings.rolling_resistance = 0.1f;
  CHECK_THROWS_AS(World(settings), hail::InvalidArgument);
  settings.rolling_resistance = 0.0f;
  CHECK_NOTHROW(World(settings));
}

TEST_CASE("B: a sliding sphere switches to rolling at 5/7 v0 at t*", "[known][friction]") {
  const float dt = 1.0f / 1000, mu = 0.3f, v0 = 5.0f, g = 9.81f;
  WorldSettings settings;
  settings.threads = 1;
  settings.solver = GENERATE(Solver::Passes, Solver::SoftStep);  // the soft step: the same friction rule
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0, .friction = mu});
  const SphereId id = world.add_sphere(
      {.position = {0, 0.5f, 0}, .velocity = {v0, 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 0, .friction = mu});
  double switch_time = -1;
  for (int k = 1; k <= 1500; ++k) {
    world.step(dt);
    const Vec3 v = world.velocity(id), w = world.angular_velocity(id);
    const double slip = v.x() + w.z() * 0.5;  // contact point velocity: v + w x (0, -r, 0)
    if (switch_time < 0 && std::abs(slip) < 1e-3) switch_time = k * dt;
  }
  const double t_star = 2 * v0 / (7 * mu * g);
  const double rolling = 5.0 / 7.0 * v0;
  const double speed = world.velocity(id).norm();
  INFO("final speed " << speed << " (exact " << rolling << "), switch at " << switch_time << " s (exact " << t_star
                      << ")");
  CHECK(std::abs(speed - rolling) <= 0.01 * rolling);
  CHECK(std::abs(switch_time - t_star) <= 0.02);
  CHECK(std::abs(world.position(id).y() - 0.5) < 1e-3);
}

TEST_CASE("C: head-on collision gives the 1-D elastic formulas", "[known][sphere-sphere]") {
  const double m2 = GENERATE(1.0, 1000.0);
  const double m1 = 1.0;
  WorldSettings settings;
  settings.gravity = Vec3::Zero();
  settings.threads = 1;
  // The soft step: one contact, restitution from its approach speed, the same answer.
  settings.solver = GENERATE(Solver::Passes, Solver::SoftStep);
  World world(settings);
  const SphereId a = world.add_sphere({.position = {-2, 0, 0},
                                       .velocity = {10, 0, 0},
                                       .radius = 0.5f,
                                       .mass = float(m1),
                                       .restitution = 1,
                                       .friction = 0});
  const SphereId b =
      world.add_sphere({.position = {2, 0, 0}, .radius = 0.5f, .mass = float(m2), .restitution = 1, .friction = 0});
  const Eigen::Vector3d p0 = world.linear_momentum();
  for (int k = 0; k < 120; ++k) world.step(1.0f / 60);
  const double v1 = (m1 - m2) / (m1 + m2) * 10.0, v2 = 2 * m1 / (m1 + m2) * 10.0;
  INFO("m2 = " << m2 << ": v1' = " << world.velocity(a).x() << " (exact " << v1 << "), v2' = " << world.velocity(b).x()
               << " (exact " << v2 << ")");
  CHECK(std::abs(world.velocity(a).x() - v1) <= 1e-4 * std::abs(v1));
  CHECK(std::abs(world.velocity(b).x() - v2) <= 1e-4 * std::abs(v2));
  // Float rounding of the momentum sum: a few ulps of the largest term.
  CHECK((world.linear_momentum() - p0).norm() <= 1e-5 * (m1 * 10.0));
}

TEST_CASE("D: Newton's cradle sends only the far sphere away", "[known][sphere-sphere]") {
  Cradle cradle(-1.5f);
  World& world = *cradle.world;
  for (int k = 0; k < 120; ++k) world.step(1.0f / 60);
  CHECK(std::abs(world.velocity(cradle.row[4]).x() - 1.0) <= 0.01);
  for (int k = 0; k < 4; ++k) {
    INFO("sphere " << k << " v = " << world.velocity(cradle.row[k]).x());
    CHECK(std::abs(world.velocity(cradle.row[k]).x()) <= 0.01);
  }
  CHECK(std::abs(world.velocity(cradle.striker).x()) <= 0.01);
}

TEST_CASE("D: the cradle's pulse crosses the resting row in the step of the impact", "[known][sphere-sphere][margin]") {
  // Touching spheres at rest close at 0 m/s, so their own speculative margin
  // (WorldSettings::pair_margin_travel) was 0 and the strict pair test left them without a
  // contact: the pulse moved one sphere per step and the far sphere left 4 steps after the
  // impact. A resting pair within a small slop keeps its contact (kernel/world/step_pipeline.cpp).
  const float striker_start = GENERATE(-1.5f, -1.0f);  // 0.5 m away, or already touching
  Cradle cradle(striker_start);
  World& world = *cradle.world;
  int impact_step = -1, far_leaves = -1;
  for (int k = 0; k < 60 && far_leaves < 0; ++k) {
    world.step(1.0f / 60);
    if (impact_step < 0 && world.velocity(cradle.striker).x() < 0.5f) impact_step = k;
    if (world.velocity(cradle.row[4]).x() > 0.5f) far_leaves = k;
  }
  INFO("striker from x = " << striker_start << ": impact in step " << impact_step << ", far sphere leaves in step "
                           << far_leaves);
  REQUIRE(impact_step >= 0);
  CHECK(far_leaves == impact_step);
  CHECK(std::abs(world.velocity(cradle.row[4]).x() - 1.0) <= 1e-5);
  for (int k = 0; k < 4; ++k) CHECK(std::abs(world.velocity(cradle.row[k]).x()) <= 1e-5);
}

TEST_CASE("D: the soft step's cradle keeps momentum and energy but spreads the pulse", "[known][sphere-sphere][soft]") {
  // The soft step solves the row's contacts together, a few iterations a substep, and applies
  // restitution once per contact from the speed at which it approached when the step began:
  // the resting joints approached at 0 m/s, so they get no restitution, and the striker's
  // momentum is shared along the row instead of passed to the far sphere alone. Measured
  // (dt 1/60, defaults): the far sphere leaves at 0.32 m/s (the textbook answer: 1 m/s), the
  // six spheres keep 0.14 J of the striker's 0.5 J; hail-bench accuracy's D-cradle error is
  // 0.68 (the passes: 0). What holds: momentum exactly, and no energy gained.
  Cradle cradle(-1.5f, Solver::SoftStep);
  World& world = *cradle.world;
  for (int k = 0; k < 120; ++k) world.step(1.0f / 60);
  double momentum = world.velocity(cradle.striker).x(), energy = 0.5 * std::pow(world.velocity(cradle.striker).x(), 2);
  for (const SphereId id : cradle.row) {
    momentum += world.velocity(id).x();
    energy += 0.5 * std::pow(world.velocity(id).x(), 2);
  }
  const double far = world.velocity(cradle.row[4]).x();
  INFO("soft cradle: far sphere " << far << " m/s, momentum " << momentum << ", energy " << energy << " J");
  CHECK(std::abs(momentum - 1.0) <= 1e-5);
  CHECK(energy <= 0.5 + 1e-6);
  CHECK(std::abs(far - 0.32) <= 0.02);  // the deviation stated above
  CHECK(std::abs(energy - 0.14) <= 0.02);
}
