// Brute-force sphere-sphere pair test, SIMD vs its scalar reference: pairs tested per second
// (n(n-1)/2 per call), the inner loop every other pair search falls back on.
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/broadphase/sphere_pairs.h"
#include "micro_data.h"

namespace hail::micro {
namespace {

constexpr float kMargin = 0.1f;

template <bool Simd>
void sphere_pairs(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const SphereSoA spheres = make_cloud(Cloud::Mixed, n, 11);
  std::vector<SpherePair> out;
  out.reserve(n * 8);
  for (auto _ : state) {
    out.clear();
    if constexpr (Simd)
      find_sphere_pairs_simd(spheres, 0, n, kMargin, out);
    else
      find_sphere_pairs_scalar(spheres, 0, n, kMargin, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n * (n - 1) / 2));
  state.SetLabel("items = pairs tested");
  state.counters["pairs_found"] = static_cast<double>(out.size());
}

BENCHMARK(sphere_pairs<false>)->Name("sphere_pairs/scalar")->ArgName("n")->Arg(1000)->Arg(4000);
BENCHMARK(sphere_pairs<true>)->Name("sphere_pairs/simd")->ArgName("n")->Arg(1000)->Arg(4000);

}  // namespace
}  // namespace hail::micro
