// One collision pass and one resting pass over a colour of contacts, the staged SIMD batches
// (ContactBatches) vs the scalar rules they must equal bit for bit: contacts per second.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/solver/contact_solve_simd.h"

namespace hail::micro {
namespace {

/// `count` contacts over 2 * count bodies, each body in at most one contact (one colour), plus
/// the static body: tests/test_contact_solve_simd.cpp's random run (30% static contacts, 10%
/// immovable spheres, half the gaps speculative, impulses carried over).
struct Run {
  std::vector<SolverBody> bodies;
  std::vector<Contact> contacts;
};

Run random_run(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  Run run;
  run.bodies.resize(2 * count + 1);
  for (SolverBody& b : std::span(run.bodies).first(2 * count)) {
    for (int d = 0; d < 3; ++d) b.v[d] = 5.0f * u(rng), b.w[d] = 3.0f * u(rng);
    b.radius = 0.1f + unit(rng);
    const bool fixed = unit(rng) < 0.1f;
    b.inv_mass = fixed ? 0.0f : 0.2f + 2.0f * unit(rng);
    b.inv_inertia = fixed ? 0.0f : b.inv_mass / (0.4f * b.radius * b.radius);
  }
  std::vector<std::uint32_t> slot(2 * count);
  std::iota(slot.begin(), slot.end(), 0u);
  std::shuffle(slot.begin(), slot.end(), rng);  // bodies at random, as colour order visits them
  for (std::size_t k = 0; k < count; ++k) {
    Contact c;
    c.a = slot[2 * k];
    c.b = unit(rng) < 0.3f ? kStaticBody : slot[2 * k + 1];
    const float n[3] = {u(rng), u(rng), u(rng)};
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-3f;
    c.nx = n[0] / len, c.ny = n[1] / len, c.nz = n[2] / len;
    c.gap = 0.2f * u(rng);
    c.restitution = unit(rng);
    c.friction = unit(rng) < 0.2f ? 0.0f : unit(rng);
    c.normal_impulse = unit(rng) < 0.5f ? 0.0f : unit(rng);
    c.tx = 0.1f * u(rng), c.ty = 0.1f * u(rng), c.tz = 0.1f * u(rng);
    run.contacts.push_back(c);
  }
  return run;
}

enum class Pass { Collision, Resting };

// A pass changes velocities and impulses, and a repeated pass on settled contacts would let
// the scalar rules return early where the SIMD lanes cannot, so every iteration starts from
// the same run: it is restored (and re-staged) untimed, and only the pass is timed.
template <Pass P, bool Simd>
void solve(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  const Run start = random_run(count, 61);
  Run run = start;
  const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(count)};
  ContactBatches batches;
  batches.stage(run.contacts, colour_begin, 1, run.bodies);
  const std::span<Contact> tail = std::span(run.contacts).subspan(batches.tail_begin(0));
  const float dt = 1.0f / 60.0f;
  for (auto _ : state) {
    std::copy(start.bodies.begin(), start.bodies.end(), run.bodies.begin());
    std::copy(start.contacts.begin(), start.contacts.end(), run.contacts.begin());
    if constexpr (Simd) batches.stage(run.contacts, colour_begin, 1, run.bodies);
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (Simd) {
      if constexpr (P == Pass::Collision) {
        benchmark::DoNotOptimize(batches.solve_collision(0, batches.batch_end(0), run.bodies, dt, 1.0f, 0));
        benchmark::DoNotOptimize(solve_collision_run_scalar(tail, run.bodies, dt, 1.0f, 0));
      } else {
        batches.solve_resting(0, batches.batch_end(0), run.bodies, 1.0f / dt);
        solve_resting_run_scalar(tail, run.bodies, 1.0f / dt);
      }
    } else {
      if constexpr (P == Pass::Collision)
        benchmark::DoNotOptimize(solve_collision_run_scalar(run.contacts, run.bodies, dt, 1.0f, 0));
      else
        solve_resting_run_scalar(run.contacts, run.bodies, 1.0f / dt);
    }
    benchmark::ClobberMemory();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * count));
  state.SetLabel("items = contacts");
}

BENCHMARK(solve<Pass::Resting, false>)->Name("solver/resting_pass/scalar")->ArgName("contacts")->Arg(4096)->Arg(32768)->UseManualTime();
BENCHMARK(solve<Pass::Resting, true>)->Name("solver/resting_pass/simd")->ArgName("contacts")->Arg(4096)->Arg(32768)->UseManualTime();
BENCHMARK(solve<Pass::Collision, false>)->Name("solver/collision_pass/scalar")->ArgName("contacts")->Arg(4096)->Arg(32768)->UseManualTime();
BENCHMARK(solve<Pass::Collision, true>)->Name("solver/collision_pass/simd")->ArgName("contacts")->Arg(4096)->Arg(32768)->UseManualTime();

}  // namespace
}  // namespace hail::micro
