// Each sphere-sphere pair search (brute-force SIMD, uniform grid, sort-and-sweep, sphere BVH),
// build + find_pairs over all rows on one thread, spheres per second: the crossovers that
// WorldSettings::pair_search = Automatic relies on.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/sphere_bvh_pairs.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "micro_data.h"

namespace hail::micro {
namespace {

constexpr float kMargin = 0.1f;

enum class Search { Brute, Grid, Sweep, Bvh };

template <Search S>
void broadphase(benchmark::State& state, Cloud cloud, std::size_t n) {
  const SphereSoA spheres = make_cloud(cloud, n, cloud == Cloud::Rain ? 51 : 52);
  SphereGrid grid;
  SortedAxisPairs sweep;
  SphereBvhPairs bvh;
  std::vector<SpherePair> out;
  std::vector<std::uint32_t> row;
  out.reserve(16 * n);
  for (auto _ : state) {
    out.clear();
    if constexpr (S == Search::Brute) {
      find_sphere_pairs_simd(spheres, 0, n, kMargin, out);
    } else if constexpr (S == Search::Grid) {
      grid.build(spheres, kMargin);
      grid.find_pairs(spheres, 0, n, kMargin, out, row);
    } else if constexpr (S == Search::Sweep) {
      sweep.build(spheres, kMargin);
      sweep.find_pairs(spheres, 0, n, kMargin, out, row);
    } else {
      bvh.build(spheres, kMargin);
      bvh.find_pairs(spheres, 0, n, kMargin, out, row);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.SetLabel("items = spheres");
  state.counters["pairs"] = static_cast<double>(out.size());
}

const bool kRegistered = [] {
  using Fn = void (*)(benchmark::State&, Cloud, std::size_t);
  const std::pair<const char*, Fn> searches[] = {{"broadphase/brute_simd", broadphase<Search::Brute>},
                                                 {"broadphase/grid", broadphase<Search::Grid>},
                                                 {"broadphase/sweep", broadphase<Search::Sweep>},
                                                 {"broadphase/bvh", broadphase<Search::Bvh>}};
  for (Cloud cloud : {Cloud::Rain, Cloud::Mixed})
    for (std::size_t n : {4000, 16000})
      for (const auto& [name, fn] : searches)
        benchmark::RegisterBenchmark((std::string(name) + "/" + name_of(cloud) + "/n:" + std::to_string(n)).c_str(),
                                     [fn = fn, cloud, n](benchmark::State& state) { fn(state, cloud, n); })
            ->Unit(benchmark::kMicrosecond);
  return true;
}();

}  // namespace
}  // namespace hail::micro
