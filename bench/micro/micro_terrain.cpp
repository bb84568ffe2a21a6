// The terrain BVH walks on terrain-rain's terrain (130k triangles), queries per second, in
// random and Morton order: stackless vs fixed-stack sphere walk, box, ray and swept-sphere walks,
// the packet walk (4, 8 or 16 lanes: the active SIMD path), and Terrain::find_contacts (the detect phase's terrain half) per sphere.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/broadphase/spatial_order.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/ray_triangle.h"
#include "kernel/geometry/swept_sphere.h"
#include "micro_data.h"

namespace hail::micro {
namespace {

constexpr std::size_t kQueries = 4096;
constexpr float kDt = 1.0f / 60.0f;

/// Ends a walk benchmark: items are queries, and `hits` (what the last pass found) is kept
/// beside the time so that methods that must agree can be seen to.
void finish(benchmark::State& state, std::uint64_t hits) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kQueries));
  state.SetLabel("items = queries");
  state.counters["hits_per_query"] = double(hits) / kQueries;
}

// Sphere walks count the triangles whose box the sphere touches (leaf candidates filtered by
// their own boxes), the result the packet walk's SIMD leaf filter gives, so all four agree.
void sphere_stackless(benchmark::State& state, Order order) {
  const FlatBvh& bvh = rain_terrain().bvh();
  const std::span<const Aabb> bounds = rain_triangle_bounds();
  const std::vector<Query> queries = resting_queries(kQueries, order, 41);
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const Query& q : queries)
      query_sphere(bvh, q.x, q.y, q.z, q.r,
                   [&](std::uint32_t k) { hits += sphere_overlaps(bounds[k], q.x, q.y, q.z, q.r); });
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

void sphere_stack(benchmark::State& state, Order order) {
  const FlatBvh& bvh = rain_terrain().bvh();
  const std::span<const Aabb> bounds = rain_triangle_bounds();
  const std::vector<Query> queries = resting_queries(kQueries, order, 41);
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const Query& q : queries)
      query_sphere_stack(bvh, q.x, q.y, q.z, q.r,
                         [&](std::uint32_t k) { hits += sphere_overlaps(bounds[k], q.x, q.y, q.z, q.r); });
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

void sphere_packet(benchmark::State& state, Order order) {
  // The packet walk with SIMD leaf boxes of the active SIMD path (HAIL_SIMD chooses another).
  const FlatBvh& bvh = rain_terrain().bvh();
  const std::span<const Aabb> bounds = rain_triangle_bounds();
  const std::vector<Query> queries = resting_queries(kQueries, order, 41);
  std::vector<float> x, y, z, r;
  for (const Query& q : queries) x.push_back(q.x), y.push_back(q.y), z.push_back(q.z), r.push_back(q.r);
  const SimdKernels& kernels = simd_kernels();
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = kernels.count_packet_hits(bvh, bounds.data(), x.data(), y.data(), z.data(), r.data(), queries.size(),
                                     PacketLeafTest::LeafBoxes, nullptr);
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

void box_walk(benchmark::State& state, Order order) {
  const FlatBvh& bvh = rain_terrain().bvh();
  const std::span<const Aabb> bounds = rain_triangle_bounds();
  const std::vector<Query> queries = resting_queries(kQueries, order, 41);
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const Query& q : queries) {
      const Aabb box{{q.x - q.r, q.y - q.r, q.z - q.r}, {q.x + q.r, q.y + q.r, q.z + q.r}};
      query_aabb(bvh, box, [&](std::uint32_t k) { hits += overlaps(bounds[k], box); });
    }
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

// Ray and swept walks follow the fast falling paths continuous collision sweeps (up to 5 m a step).
void ray_walk(benchmark::State& state, Order order) {
  const FlatBvh& bvh = rain_terrain().bvh();
  const TerrainTriangles& t = rain_terrain().triangles();
  const std::vector<Query> paths = falling_queries(kQueries, order, 42);
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const Query& q : paths) {
      const float o[3] = {q.x, q.y, q.z}, d[3] = {q.vx, q.vy, q.vz};
      const RayHit hit = query_ray(bvh, o, d, kDt, [&](std::uint32_t k) {
        const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]};
        const float c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
        return ray_triangle(o, d, a, b, c);
      });
      hits += hit.primitive != kNoPrimitive;
    }
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

void swept_walk(benchmark::State& state, Order order) {
  const FlatBvh& bvh = rain_terrain().bvh();
  const TerrainTriangles& t = rain_terrain().triangles();
  const std::vector<Query> paths = falling_queries(kQueries, order, 42);
  std::uint64_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const Query& q : paths) {
      const float o[3] = {q.x, q.y, q.z}, d[3] = {q.vx, q.vy, q.vz};
      const double c[3] = {q.x, q.y, q.z}, v[3] = {q.vx, q.vy, q.vz};
      // As continuous collision walks it: node boxes grown by r, each candidate timed in double.
      const RayHit hit = query_swept_sphere(bvh, o, d, kDt, q.r, [&](std::uint32_t k) {
        const double a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]};
        const double cc[3] = {t.v2x[k], t.v2y[k], t.v2z[k]}, n[3] = {t.nx[k], t.ny[k], t.nz[k]};
        SweptHit sh;
        if (!swept_sphere_triangle(c, v, q.r, a, b, cc, n, t.internal_edges[k], kDt, sh)) return -1.0f;
        return static_cast<float>(sh.t);
      });
      hits += hit.primitive != kNoPrimitive;
    }
    benchmark::DoNotOptimize(hits);
  }
  finish(state, hits);
}

void find_contacts(benchmark::State& state, Order order) {
  // The spheres in an SoA, Morton order as World's periodic re-sort (morton_slot_order) makes it.
  const Terrain& terrain = rain_terrain();
  SphereSoA spheres;
  spheres.reserve(kQueries);
  for (const Query& q : resting_queries(kQueries, Order::Random, 41))
    add_sphere(spheres, q.x, q.y, q.z, q.r, q.vx, q.vy, q.vz);
  if (order == Order::Morton) {
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> slots;
    morton_slot_order(spheres, keys, slots);
    spheres.permute(slots);
  }
  std::vector<Contact> out;
  out.reserve(8 * kQueries);
  for (auto _ : state) {
    out.clear();
    terrain.find_contacts(spheres, 0, spheres.size(), kDt, 0.5f, 0.5f, out, 1.0f, true);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kQueries));
  state.SetLabel("items = spheres");
  state.counters["contacts_per_sphere"] = double(out.size()) / kQueries;
}

const bool kRegistered = [] {
  using Fn = void (*)(benchmark::State&, Order);
  const std::pair<const char*, Fn> methods[] = {{"terrain/sphere_stackless", sphere_stackless},
                                                {"terrain/sphere_stack", sphere_stack},
                                                {"terrain/sphere_packet_exact", sphere_packet},
                                                {"terrain/aabb", box_walk},
                                                {"terrain/ray", ray_walk},
                                                {"terrain/swept_sphere", swept_walk},
                                                {"terrain/find_contacts", find_contacts}};
  for (const auto& [name, fn] : methods)
    for (Order order : {Order::Random, Order::Morton})
      benchmark::RegisterBenchmark((std::string(name) + "/" + name_of(order)).c_str(),
                                   [fn = fn, order](benchmark::State& state) { fn(state, order); });
  return true;
}();

}  // namespace
}  // namespace hail::micro
