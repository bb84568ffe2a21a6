// Continuous collision's pieces: swept sphere-triangle and sphere-sphere time of impact per
// test (double, run only for fast spheres), and the path-box scan every fast sphere makes over
// all spheres, SIMD vs scalar (spheres scanned per second).
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/bvh/flat_bvh.h"
#include "kernel/ccd/path_box_scan.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/swept_sphere.h"
#include "micro_data.h"

namespace hail::micro {
namespace {

constexpr std::size_t kTests = 4096;
constexpr double kDt = 1.0 / 60.0;

void swept_triangle(benchmark::State& state) {
  // Fast falling spheres (falling_queries), each against the terrain triangle its path hits
  // first, or, for the paths that end above the ground, the first triangle under its start.
  const TerrainTriangles& t = rain_terrain().triangles();
  const FlatBvh& bvh = rain_terrain().bvh();
  const std::vector<Query> paths = falling_queries(kTests, Order::Random, 31);
  std::vector<std::uint32_t> tri(kTests);
  for (std::size_t k = 0; k < kTests; ++k) {
    const Query& q = paths[k];
    const double c[3] = {q.x, q.y, q.z}, v[3] = {q.vx, q.vy, q.vz};
    const float o[3] = {q.x, q.y, q.z}, d[3] = {q.vx, q.vy, q.vz};
    const RayHit first = query_swept_sphere(bvh, o, d, float(kDt), q.r, [&](std::uint32_t i) {
      const double a[3] = {t.v0x[i], t.v0y[i], t.v0z[i]}, b[3] = {t.v1x[i], t.v1y[i], t.v1z[i]};
      const double cc[3] = {t.v2x[i], t.v2y[i], t.v2z[i]}, n[3] = {t.nx[i], t.ny[i], t.nz[i]};
      SweptHit hit;
      return swept_sphere_triangle(c, v, q.r, a, b, cc, n, t.internal_edges[i], kDt, hit) ? float(hit.t) : -1.0f;
    });
    tri[k] = first.primitive;
    if (tri[k] == kNoPrimitive) {
      const Aabb column{{q.x, -1e3f, q.z}, {q.x, 1e3f, q.z}};
      tri[k] = 0;
      bool found = false;
      query_aabb(bvh, column, [&](std::uint32_t i) {
        if (!found) tri[k] = i, found = true;
      });
    }
  }
  std::uint32_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (std::size_t k = 0; k < kTests; ++k) {
      const Query& q = paths[k];
      const std::uint32_t i = tri[k];
      const double c[3] = {q.x, q.y, q.z}, v[3] = {q.vx, q.vy, q.vz};
      const double a[3] = {t.v0x[i], t.v0y[i], t.v0z[i]}, b[3] = {t.v1x[i], t.v1y[i], t.v1z[i]};
      const double cc[3] = {t.v2x[i], t.v2y[i], t.v2z[i]}, n[3] = {t.nx[i], t.ny[i], t.nz[i]};
      SweptHit hit;
      hits += swept_sphere_triangle(c, v, q.r, a, b, cc, n, t.internal_edges[i], kDt, hit);
      benchmark::DoNotOptimize(hit);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kTests));
  state.SetLabel("items = swept sphere-triangle tests");
  state.counters["hit_fraction"] = double(hits) / kTests;
}
BENCHMARK(swept_triangle)->Name("sweep/sphere_triangle_toi");

void sphere_sphere_toi(benchmark::State& state) {
  // Relative positions 0..4 m apart, relative velocities up to 300 m/s, reach 1: about half
  // touch within the step.
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> pos(-2.0, 2.0), vel(-300.0, 300.0);
  std::vector<double> dp(3 * kTests), dv(3 * kTests);
  for (double& x : dp) x = pos(rng);
  for (double& x : dv) x = vel(rng);
  std::uint32_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (std::size_t k = 0; k < kTests; ++k) {
      const double t = sphere_sphere_time_of_impact(&dp[3 * k], &dv[3 * k], 1.0, kDt);
      hits += t >= 0.0;
      benchmark::DoNotOptimize(t);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kTests));
  state.SetLabel("items = sphere-sphere TOI tests");
  state.counters["hit_fraction"] = double(hits) / kTests;
}
BENCHMARK(sphere_sphere_toi)->Name("sweep/sphere_sphere_toi");

template <bool Simd>
void path_scan(benchmark::State& state) {
  // One fast sphere's path box (a 5 m drop through the middle of a rain cloud, grown by its
  // radius) against every sphere's path over the step.
  const auto n = static_cast<std::size_t>(state.range(0));
  const SphereSoA spheres = make_cloud(Cloud::Rain, n, 33);
  const float cx = spheres.px[n / 2], cy = spheres.py[n / 2], cz = spheres.pz[n / 2];
  const PathBox box{{cx - 0.5f, cy - 5.5f, cz - 0.5f}, {cx + 0.5f, cy + 0.5f, cz + 0.5f}};
  std::uint32_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    auto visit = [&](std::uint32_t) { ++hits; };
    if constexpr (Simd)
      simd_kernels().scan_path_boxes(spheres, box, 0.0f, float(kDt), slot_sink(visit));  // the active SIMD path
    else
      scan_path_boxes_scalar(spheres, box, 0.0f, float(kDt), visit);
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.SetLabel("items = spheres scanned");
  state.counters["candidates"] = hits;
}
BENCHMARK(path_scan<false>)->Name("sweep/path_box_scan/scalar")->ArgName("n")->Arg(4000)->Arg(16000)->Arg(64000);
BENCHMARK(path_scan<true>)->Name("sweep/path_box_scan/simd")->ArgName("n")->Arg(4000)->Arg(16000)->Arg(64000);

}  // namespace
}  // namespace hail::micro
