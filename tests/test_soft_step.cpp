// The soft step (Solver::SoftStep, kernel/solver/soft_step.h): its SIMD passes give bitwise the
// state of their scalar reference on random contacts, on every SIMD path this CPU supports and
// in each FrictionWork mode; a world stepped with it is bitwise the same for any thread count
// and SIMD path; it leaves spheres in no contact exactly as the passes do; and it holds a
// resting sphere and a pile up.

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <span>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/soft_step.h"
#include "scenes/solver_problems.h"
#include "simd_paths.h"

using namespace hail;

namespace {

using Problem = hail::bench::SolverProblem;
using hail::bench::same_bits;

/// random_contacts with displacements since the step began, so that separations differ from
/// the gaps (some contacts open, some close), and gravity scales.
Problem random_soft_run(std::size_t count, std::uint32_t seed) {
  Problem p = hail::bench::random_contacts(count, seed);
  std::mt19937 rng(seed ^ 0x5eedu);
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);
  for (std::size_t i = 0; i + 1 < p.bodies.size(); ++i) {
    SolverBody& b = p.bodies[i];
    for (float& d : b.dp) d = u(rng);
    b.gravity_scale = b.inv_mass > 0.0f ? 1.0f : 0.0f;
  }
  return p;
}

SoftPass soft_pass(SoftPassKind kind, float factor) {
  const float h = 1.0f / 240.0f;
  SoftPass p;
  p.kind = kind;
  p.inv_h = 1.0f / h;
  p.contact = make_soft(30.0f, 10.0f, h);
  p.ground = make_soft(60.0f, 10.0f, h);
  p.max_push_speed = 3.0f;
  p.restitution_threshold = 0.5f;
  p.impulse_factor = factor;
  return p;
}

/// A whole soft step's contact work over one colour holding every contact of p: prepare, two
/// substeps (warm start, solve, move, relax), restitution; SIMD batches (the last padded) or
/// (simd false) the scalar rules alone.
void run_soft(Problem& p, bool simd, FrictionWork work) {
  const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(p.contacts.size())};
  ContactBatches batches;
  batches.stage(p.contacts, colour_begin, 1, p.bodies);
  const std::size_t batched = simd ? batches.batch_end(0) : 0;
  const std::span<Contact> rest = std::span(p.contacts).subspan(simd ? batches.tail_begin(0) : 0);
  auto pass = [&](const SoftPass& sp) {
    if (simd) batches.solve_soft(0, batched, p.bodies, sp, work);
    soft_run_scalar(rest, p.bodies, sp, work);
  };
  const std::size_t n = p.bodies.size() - 1;
  pass(soft_pass(SoftPassKind::Prepare, 0.5f));
  const float g_h[3] = {0.0f, -9.81f / 240.0f, 0.0f};
  for (int k = 0; k < 2; ++k) {
    if (k > 0) soft_add_gravity(p.bodies, 0, n, g_h);
    if (simd) batches.warm_start(0, batched, p.bodies, work);
    warm_start_run_scalar(rest, p.bodies, work);
    pass(soft_pass(SoftPassKind::Solve, 1.0f));
    soft_move(p.bodies, 0, n, 1.0f / 240.0f);
    pass(soft_pass(SoftPassKind::Relax, 1.0f));
  }
  pass(soft_pass(SoftPassKind::Restitution, 2.0f));
  if (simd) batches.store_impulses(p.contacts);
}

std::vector<FrictionWork> friction_modes() {
  constexpr FrictionWork kAll[] = {kNoFriction, kLinearFriction, kWithFriction};
  return std::vector<FrictionWork>(std::begin(kAll), std::end(kAll));
}

/// A 600-sphere cloud falling onto a floor between two walls, stepped with the soft step.
std::uint64_t run_soft_cloud(int threads, int steps, Solver solver = Solver::SoftStep) {
  WorldSettings settings;
  settings.threads = threads;
  settings.solver = solver;
  const std::size_t tile_spheres = 128;  // several tiles, and contacts between them
  settings.solver_tile_spheres = tile_spheres;
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.3f, .friction = 0.6f});
  world.add_plane({.normal = {1, 0, 0}, .offset = -6, .restitution = 0.3f, .friction = 0.6f});
  world.add_plane({.normal = {-1, 0, 0}, .offset = -6, .restitution = 0.3f, .friction = 0.6f});
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int k = 0; k < 600; ++k)
    world.add_sphere({.position = {5.0f * u(rng), 5.0f + 4.0f * u(rng), 5.0f * u(rng)},
                      .velocity = {2.0f * u(rng), 2.0f * u(rng), 2.0f * u(rng)},
                      .radius = 0.25f + 0.05f * u(rng),
                      .mass = 1.0f + 0.5f * u(rng),
                      .restitution = 0.4f,
                      .friction = 0.5f});
  for (int k = 0; k < steps; ++k) world.step(1.0f / 60.0f);
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("SIMD soft-step passes equal their scalar reference bit for bit", "[solver][simd][soft]") {
  const std::size_t count = GENERATE(1, 7, 9, 16, 23, 256, 1001);
  const FrictionWork work = GENERATE(from_range(friction_modes()));
  for (SimdPath path : hail::testing::supported_paths()) {
    const hail::testing::ScopedSimdPath scoped(path);
    INFO(count << " contacts, friction mode " << int(work) << ", path " << simd_path_name(path));
    const auto seed = static_cast<std::uint32_t>(count * 17 + 3);
    Problem simd = random_soft_run(count, seed), scalar = simd;
    run_soft(simd, true, work);
    run_soft(scalar, false, work);
    CHECK(same_bits(simd, scalar));  // velocities, displacements, every impulse and bounce
    // The passes did something, and (in the larger runs) some contact ends the step pushing.
    CHECK_FALSE(same_bits(simd, random_soft_run(count, seed)));
    if (count >= 23)
      CHECK(std::any_of(scalar.contacts.begin(), scalar.contacts.end(),
                        [](const Contact& c) { return c.normal_impulse > 0.0f; }));
    const SolverBody& fixed = simd.bodies.back();  // the static body was never written
    CHECK((fixed.v[0] == 0.0f && fixed.v[1] == 0.0f && fixed.v[2] == 0.0f && fixed.dp[1] == 0.0f));
  }
}

TEST_CASE("The soft step is bitwise the same for 1, 2 and 3 threads and every SIMD path", "[determinism][soft]") {
  const std::uint64_t one = run_soft_cloud(1, 180);
  CHECK(run_soft_cloud(2, 180) == one);
  CHECK(run_soft_cloud(3, 180) == one);
  for (SimdPath path : hail::testing::supported_paths()) {
    const hail::testing::ScopedSimdPath scoped(path);
    INFO("path " << simd_path_name(path));
    CHECK(run_soft_cloud(2, 180) == one);
  }
  // The soft step ran: the passes give another state. And they stay the default.
  CHECK(run_soft_cloud(2, 180, Solver::Passes) != one);
  CHECK(WorldSettings{}.solver == Solver::Passes);
}

TEST_CASE("The soft step leaves a sphere in no contact as the passes do", "[soft]") {
  auto fall = [](Solver solver) {
    WorldSettings settings;
    settings.threads = 1;
    settings.solver = solver;
    World world(settings);
    world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.5f, .friction = 0.5f});
    const SphereId id = world.add_sphere({.position = {0, 20, 0}, .velocity = {1, 0, 0}, .radius = 0.5f, .mass = 1});
    world.add_sphere({.position = {10, 0.5f, 0}, .radius = 0.5f, .mass = 1});  // on the ground: the solve runs
    for (int k = 0; k < 60; ++k) world.step(1.0f / 60.0f);                     // 1 s: still 14 m up
    return std::pair{world.position(id), world.velocity(id)};
  };
  const auto [p_passes, v_passes] = fall(Solver::Passes);
  const auto [p_soft, v_soft] = fall(Solver::SoftStep);
  CHECK(p_passes.y() > 10.0f);
  CHECK(p_soft == p_passes);
  CHECK(v_soft == v_passes);
}

TEST_CASE("The soft step holds a resting sphere and a column of five on the ground", "[soft]") {
  WorldSettings settings;
  settings.threads = 1;
  settings.solver = Solver::SoftStep;
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.0f, .friction = 0.5f});
  std::vector<SphereId> column;
  for (int k = 0; k < 5; ++k)
    column.push_back(world.add_sphere({.position = {0, 0.5f + float(k), 0}, .radius = 0.5f, .mass = 1}));
  const SphereId alone = world.add_sphere({.position = {5, 0.5f, 0}, .radius = 0.5f, .mass = 1});
  for (int k = 0; k < 300; ++k) world.step(1.0f / 60.0f);  // 5 s
  CHECK(world.position(alone).y() == Approx(0.5).margin(0.005));
  CHECK(std::abs(world.velocity(alone).y()) < 0.01f);
  for (int k = 0; k < 5; ++k) {
    INFO("sphere " << k << " of the column");
    // Within 1% of a radius of touching (the soft contacts give a little under the weight above).
    CHECK(world.position(column[k]).y() == Approx(0.5 + k).margin(0.005 * (k + 1)));
    CHECK(std::abs(world.position(column[k]).x()) < 0.01f);
  }
}

TEST_CASE("The soft step's depenetration goes on while an overlap is deep, up to its maximum", "[soft]") {
  // Eight spheres of radius 0.1 mm touching in two layers on a plane (the stress case
  // radius-1e-4-and-1e4): a substep's gravity moves them 1.7 radii, and the soft contact sags a
  // share of the radius under the upper layer. Returns the deepest ground overlap over 60 steps
  // as a share of the radius, and the depenetration passes of the first step and of the last.
  struct Run {
    float deepest = 0.0f;
    int first_passes = 0, last_passes = 0;
  };
  auto pile = [](Solver solver, int most) {
    WorldSettings settings;
    settings.threads = 1;
    settings.solver = solver;
    settings.soft_step.depenetration_iterations_max = most;
    World world(settings);
    world.add_plane({});
    std::vector<SphereId> ids;
    for (int k = 0; k < 8; ++k)
      ids.push_back(world.add_sphere(
          {.position = {0.0002f * float(k % 2), 0.0001f + 0.0002f * float(k / 4), 0.0002f * float((k / 2) % 2)},
           .radius = 1e-4f,
           .mass = 1e-9f}));
    Run r;
    for (int step = 0; step < 60; ++step) {
      world.step(1.0f / 60.0f);
      if (step == 0) r.first_passes = world.last_step_stats().depenetration_passes;
      r.last_passes = world.last_step_stats().depenetration_passes;
      for (SphereId id : ids) r.deepest = std::max(r.deepest, (1e-4f - world.position(id).y()) / 1e-4f);
    }
    return r;
  };
  const int least = WorldSettings{}.depenetration_iterations;
  const Run soft = pile(Solver::SoftStep, 16);
  CHECK(soft.first_passes > least);
  CHECK(soft.first_passes <= 16);
  CHECK(soft.deepest < 0.05f);  // the stress battery's bound
  // Stopped at the least passes, the same pile sinks over three times as deep.
  const Run four = pile(Solver::SoftStep, least);
  CHECK(four.first_passes == least);
  CHECK(four.deepest > 0.15f);
  // The passes solver runs exactly depenetration_iterations, whatever the soft step's maximum.
  const Run passes = pile(Solver::Passes, 16);
  CHECK(passes.first_passes == least);
  CHECK(passes.last_passes == least);
  CHECK(passes.deepest < 0.05f);
}

TEST_CASE("The soft step's extra depenetration passes are for spheres whose contact sags beyond the slop", "[soft]") {
  // A column of four touching spheres on a plane, 30 steps: only spheres smaller than the
  // sag of a contact between spheres over the slop (6.9 mm at the defaults and dt 1/60) ever
  // get more than depenetration_iterations passes; the same column of larger spheres, deep as
  // its overlaps may get, never does.
  auto most_passes = [](float radius) {
    WorldSettings settings;
    settings.threads = 1;
    settings.solver = Solver::SoftStep;
    World world(settings);
    world.add_plane({});
    for (int k = 0; k < 4; ++k)
      world.add_sphere({.position = {0, radius * float(1 + 2 * k), 0}, .radius = radius, .mass = 1});
    int most = 0;
    for (int step = 0; step < 30; ++step) {
      world.step(1.0f / 60.0f);
      most = std::max(most, world.last_step_stats().depenetration_passes);
    }
    return most;
  };
  const int least = WorldSettings{}.depenetration_iterations;
  CHECK(most_passes(0.5f) == least);
  CHECK(most_passes(0.01f) == least);
  CHECK(most_passes(0.0001f) > least);
}
