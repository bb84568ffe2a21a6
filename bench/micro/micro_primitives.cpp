// Single primitive tests (sphere-box, ray-box, sphere-triangle contact) per test, on terrain
// nodes and triangles: the per-node and per-leaf costs that every BVH walk is made of.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "kernel/geometry/aabb.h"
#include "kernel/geometry/sphere_triangle.h"
#include "micro_data.h"

namespace hail::micro {
namespace {

constexpr std::size_t kTests = 4096;

/// kTests terrain BVH nodes (random, fixed seed) and a point near each: within 1.5 m of the box.
struct BoxCase {
  std::vector<FlatNode> boxes;
  std::vector<float> px, py, pz;
};

BoxCase box_cases() {
  const std::vector<FlatNode>& nodes = rain_terrain().bvh().nodes;
  std::mt19937 rng(21);
  std::uniform_int_distribution<std::size_t> pick(0, nodes.size() - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), off(-1.5f, 1.5f);
  BoxCase c;
  for (std::size_t k = 0; k < kTests; ++k) {
    const FlatNode& n = nodes[pick(rng)];
    c.boxes.push_back(n);
    // A point in the box, pushed out by up to 1.5 m per axis: about half the tests hit.
    c.px.push_back(n.min[0] + unit(rng) * (n.max[0] - n.min[0]) + off(rng));
    c.py.push_back(n.min[1] + unit(rng) * (n.max[1] - n.min[1]) + off(rng));
    c.pz.push_back(n.min[2] + unit(rng) * (n.max[2] - n.min[2]) + off(rng));
  }
  return c;
}

void sphere_box(benchmark::State& state) {
  const BoxCase c = box_cases();
  std::uint32_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (std::size_t k = 0; k < kTests; ++k) hits += sphere_overlaps(c.boxes[k], c.px[k], c.py[k], c.pz[k], 0.5f);
    benchmark::DoNotOptimize(hits);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kTests));
  state.SetLabel("items = sphere-box tests");
  state.counters["hit_fraction"] = double(hits) / kTests;
}
BENCHMARK(sphere_box)->Name("primitive/sphere_aabb");

void ray_box(benchmark::State& state) {
  const BoxCase c = box_cases();
  // Rays from the points towards random directions (5 m long): about a third hit.
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> inv_dir(3 * kTests);
  for (float& v : inv_dir) v = 1.0f / u(rng);
  std::uint32_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (std::size_t k = 0; k < kTests; ++k) {
      const float o[3] = {c.px[k], c.py[k], c.pz[k]};
      hits += ray_overlaps(c.boxes[k], o, &inv_dir[3 * k], 5.0f);
    }
    benchmark::DoNotOptimize(hits);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kTests));
  state.SetLabel("items = ray-box tests");
  state.counters["hit_fraction"] = double(hits) / kTests;
}
BENCHMARK(ray_box)->Name("primitive/ray_aabb");

void sphere_triangle(benchmark::State& state) {
  // Terrain triangles at random, each with a sphere centre near it: above the face, beside an
  // edge or a vertex, or sunk below the plane, within 1 m of the triangle's box.
  const TerrainTriangles& t = rain_terrain().triangles();
  const std::span<const Aabb> bounds = rain_triangle_bounds();
  std::mt19937 rng(23);
  std::uniform_int_distribution<std::size_t> pick(0, t.size() - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), off(-1.0f, 1.0f);
  std::vector<std::uint32_t> tri(kTests);
  std::vector<float> centre(3 * kTests);
  for (std::size_t k = 0; k < kTests; ++k) {
    tri[k] = static_cast<std::uint32_t>(pick(rng));
    const Aabb& b = bounds[tri[k]];
    for (int d = 0; d < 3; ++d) centre[3 * k + d] = b.min[d] + unit(rng) * (b.max[d] - b.min[d]) + off(rng);
  }
  std::uint32_t contacts = 0;
  for (auto _ : state) {
    contacts = 0;
    for (std::size_t k = 0; k < kTests; ++k) {
      const std::uint32_t i = tri[k];
      const float a[3] = {t.v0x[i], t.v0y[i], t.v0z[i]}, b[3] = {t.v1x[i], t.v1y[i], t.v1z[i]};
      const float c[3] = {t.v2x[i], t.v2y[i], t.v2z[i]}, n[3] = {t.nx[i], t.ny[i], t.nz[i]};
      SphereTriangleContact st;
      contacts += sphere_triangle_contact(&centre[3 * k], 0.5f, a, b, c, n, t.d[i], t.internal_edges[i], 0.1f, st);
      benchmark::DoNotOptimize(st);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kTests));
  state.SetLabel("items = sphere-triangle tests");
  state.counters["contact_fraction"] = double(contacts) / kTests;
}
BENCHMARK(sphere_triangle)->Name("primitive/sphere_triangle");

}  // namespace
}  // namespace hail::micro
