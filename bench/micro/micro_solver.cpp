// One collision pass and one resting pass over a colour of contacts, the staged SIMD batches
// (ContactBatches) vs the scalar rules they must equal bit for bit: contacts per second.
#include <algorithm>
#include <chrono>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/solver/contact_solve_simd.h"
#include "scenes/solver_problems.h"

namespace hail::micro {
namespace {

using Run = bench::SolverProblem;

enum class Pass { Collision, Resting };

// A pass changes velocities and impulses, and a repeated pass on settled contacts would let
// the scalar rules return early where the SIMD lanes cannot, so every iteration starts from
// the same run: it is restored (and re-staged) untimed, and only the pass is timed.
template <Pass P, bool Simd>
void solve(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  // `count` contacts over 2 * count bodies, each body in at most one contact (one colour), plus
  // the static body: the tests' random run, with every contact carrying impulses (none idle).
  const Run start = bench::random_contacts(count, 61, bench::StartImpulses::AllCarried);
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

BENCHMARK(solve<Pass::Resting, false>)
    ->Name("solver/resting_pass/scalar")
    ->ArgName("contacts")
    ->Arg(4096)
    ->Arg(32768)
    ->UseManualTime();
BENCHMARK(solve<Pass::Resting, true>)
    ->Name("solver/resting_pass/simd")
    ->ArgName("contacts")
    ->Arg(4096)
    ->Arg(32768)
    ->UseManualTime();
BENCHMARK(solve<Pass::Collision, false>)
    ->Name("solver/collision_pass/scalar")
    ->ArgName("contacts")
    ->Arg(4096)
    ->Arg(32768)
    ->UseManualTime();
BENCHMARK(solve<Pass::Collision, true>)
    ->Name("solver/collision_pass/simd")
    ->ArgName("contacts")
    ->Arg(4096)
    ->Arg(32768)
    ->UseManualTime();

}  // namespace
}  // namespace hail::micro
