// Integrator::UniformAcceleration at dt = 1/60 on the simple cases of docs/accuracy.md: exact
// in free flight (bounce apexes), right at rest (a sphere whose contact cancels gravity is not
// lifted, so slide-to-roll keeps its friction every step), and spheres dropped on a plane or a
// terrain come to rest. Both solvers: the soft step stores positions that integration must end
// where its substeps did (kernel/solver/soft_step.h).

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "catch.h"
#include "hail/world.h"

using hail::Integrator;
using hail::Solver;
using hail::SphereId;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;

namespace {

constexpr float kDt = 1.0f / 60;

WorldSettings uniform_settings(Solver solver) {
  WorldSettings settings;
  settings.threads = 1;
  settings.integrator = Integrator::UniformAcceleration;
  settings.solver = solver;
  return settings;
}

}  // namespace

TEST_CASE("Uniform acceleration at 1/60: bounce apexes within 0.5% of 10 e^(2n)", "[uniform][known][bounce]") {
  const Solver solver = GENERATE(Solver::Passes, Solver::SoftStep);
  World world(uniform_settings(solver));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.8f, .friction = 0});
  const SphereId id =
      world.add_sphere({.position = {0, 10.5f, 0}, .radius = 0.5f, .mass = 1, .restitution = 0.8f, .friction = 0});
  std::vector<double> apexes;
  double highest = -1.0;
  for (int k = 0; k < 1200 && apexes.size() < 3; ++k) {
    world.step(kDt);
    const double vy = world.velocity(id).y(), y = world.position(id).y() - 0.5;
    if (vy > 0) highest = std::max(highest, y);
    if (vy <= 0 && highest >= 0) apexes.push_back(std::max(highest, y)), highest = -1.0;
  }
  REQUIRE(apexes.size() == 3);
  for (int n = 1; n <= 3; ++n) {
    const double exact = 10.0 * std::pow(0.8, 2 * n);
    INFO("solver " << int(solver) << " apex " << n << " = " << apexes[n - 1] << ", exact " << exact);
    CHECK(std::abs(apexes[n - 1] - exact) <= 0.005 * exact);
  }
}

TEST_CASE("Uniform acceleration: a sphere resting on a plane is not lifted", "[uniform][rest]") {
  // The start velocity was rebuilt as v_end - g dt: for a sphere whose contact cancelled the
  // step's gravity that is +g dt, and the parabola lifted it by g dt^2 / 2 (1.4 mm) every step.
  const Solver solver = GENERATE(Solver::Passes, Solver::SoftStep);
  World world(uniform_settings(solver));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.5f, .friction = 0.5f});
  const SphereId id =
      world.add_sphere({.position = {0, 0.5f, 0}, .radius = 0.5f, .mass = 1, .restitution = 0.5f, .friction = 0.5f});
  double highest = 0.0;
  for (int k = 0; k < 120; ++k) {
    world.step(kDt);
    highest = std::max(highest, double(world.position(id).y()) - 0.5);
  }
  INFO("solver " << int(solver) << ": highest lift " << highest << " m");
  CHECK(highest < 1e-5);  // g dt^2 / 2 = 1.4e-3
  CHECK(world.velocity(id).norm() < 1e-4);
}

TEST_CASE("Uniform acceleration at 1/60: slide to roll within 0.5% (t* and 5/7 v0)", "[uniform][known][friction]") {
  const float mu = 0.3f, v0 = 5.0f, g = 9.81f;
  const Solver solver = GENERATE(Solver::Passes, Solver::SoftStep);
  World world(uniform_settings(solver));
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0, .friction = mu});
  const SphereId id = world.add_sphere(
      {.position = {0, 0.5f, 0}, .velocity = {v0, 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 0, .friction = mu});
  // The slip falls linearly while the sphere slides: the switch time is where the last two
  // sliding steps' slips extrapolate to zero (as hail-bench accuracy measures it), so that it
  // does not snap to the 1/60 grid.
  double switch_time = -1, s1 = 0, t1 = 0, s2 = 0, t2 = 0;  // the last two sliding steps
  for (int k = 1; k <= 60; ++k) {
    world.step(kDt);
    const double t = k * double(kDt);
    const double slip = world.velocity(id).x() + world.angular_velocity(id).z() * 0.5;
    if (switch_time < 0 && slip <= 1e-3 && k >= 3) switch_time = s1 > s2 ? t2 + s2 * (t2 - t1) / (s1 - s2) : t2;
    if (slip > 1e-3) s1 = s2, t1 = t2, s2 = slip, t2 = t;
  }
  const double t_star = 2 * v0 / (7 * mu * g), rolling = 5.0 / 7.0 * v0;
  const double speed = world.velocity(id).x();
  INFO("solver " << int(solver) << ": speed " << speed << " (exact " << rolling << "), switch at " << switch_time
                 << " s (exact " << t_star << ")");
  CHECK(std::abs(speed - rolling) <= 0.005 * rolling);
  CHECK(std::abs(switch_time - t_star) <= 0.005 * t_star);
  CHECK(std::abs(world.position(id).y() - 0.5) < 1e-4);
}

namespace {

/// Speed and height above `floor` of a sphere (r = 0.5, e = 0.5) dropped from 2 m after `steps`
/// steps of 1/60, on a plane, or on a terrain when `terrain` is set.
struct Settled {
  double speed, height;
};

Settled drop_and_wait(Solver solver, bool terrain, int steps) {
  World world(uniform_settings(solver));
  if (terrain)
    world.set_terrain(std::make_shared<const hail::Terrain>(hail::Heightmap::from_function(
                          9, 9, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -4.0f, .origin_z = -4.0f},
                          [](float, float) { return 0.0f; })),
                      0.5f, 0.5f);
  if (!terrain) world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.5f, .friction = 0.5f});
  const SphereId id = world.add_sphere(
      {.position = {0.3f, 2.5f, 0.2f}, .radius = 0.5f, .mass = 1, .restitution = 0.5f, .friction = 0.5f});
  for (int k = 0; k < steps; ++k) world.step(kDt);
  return {world.velocity(id).norm(), world.position(id).y() - 0.5};
}

}  // namespace

TEST_CASE("Uniform acceleration: a sphere dropped on a plane or a terrain comes to rest", "[uniform][rest]") {
  const Solver solver = GENERATE(Solver::Passes, Solver::SoftStep);
  const bool terrain = GENERATE(false, true);
  // A drop from 2 m at e = 0.5 bounces out in about 2.5 s: 400 steps leave time to spare.
  const Settled s = drop_and_wait(solver, terrain, 400);
  INFO("solver " << int(solver) << (terrain ? " terrain" : " plane") << ": speed " << s.speed << " m/s, height "
                 << s.height << " m");
  CHECK(s.speed < 1e-3);
  CHECK(std::abs(s.height) < 2e-3);
}
