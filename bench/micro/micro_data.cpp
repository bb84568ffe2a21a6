// The shared inputs of micro_data.h, and the machine context every result carries.
#include "micro_data.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include <benchmark/benchmark.h>

#include "hail/heightmap.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/morton.h"
#include "scenes/machine_info.h"
#include "scenes/scenes.h"

namespace hail::micro {
namespace {

// Printed above the table and stored in the JSON's "context", so a number travels with what it
// was measured on (machine, SIMD path, flags). Registered before Google Benchmark's main runs.
const bool kContextAdded = [] {
  benchmark::AddCustomContext("hail_cpu", bench::cpu_model());
  benchmark::AddCustomContext("hail_simd", bench::simd_description());
  benchmark::AddCustomContext("hail_packet_width", std::to_string(simd_kernels().width));
  benchmark::AddCustomContext("hail_flags", bench::build_flags());
  return true;
}();

}  // namespace

const Terrain& rain_terrain() {
  static const Terrain terrain(Heightmap::from_function(256, 256, {}, bench::terrain_rain_height), 4);
  return terrain;
}

std::span<const Aabb> rain_triangle_bounds() {
  static const std::vector<Aabb> bounds = [] {
    const TerrainTriangles& t = rain_terrain().triangles();  // already in BVH order
    std::vector<Aabb> b(t.size());
    for (std::size_t k = 0; k < b.size(); ++k) terrain_triangle_bounds(t, k, b[k].min, b[k].max);
    return b;
  }();
  return bounds;
}

Aabb rain_terrain_box() {
  const FlatNode& root = rain_terrain().bvh().nodes.front();
  Aabb box = empty_aabb();
  grow(box, root);
  return box;
}

const char* name_of(Order order) { return order == Order::Random ? "random" : "morton"; }

const char* name_of(Cloud cloud) { return cloud == Cloud::Rain ? "rain" : "mixed"; }

void sort_by_morton(std::vector<Query>& queries) {
  const Aabb box = rain_terrain_box();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(queries.size());
  for (std::uint32_t k = 0; k < queries.size(); ++k)
    keyed[k] = {morton_code_3d(box, queries[k].x, queries[k].y, queries[k].z), k};
  std::sort(keyed.begin(), keyed.end());
  std::vector<Query> sorted(queries.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) sorted[k] = queries[keyed[k].second];
  queries = std::move(sorted);
}

std::vector<Query> resting_queries(std::size_t count, Order order, std::uint32_t seed) {
  const Heightmap& map = rain_terrain().heightmap();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(1.0f, 254.0f), lift(-0.05f, 0.3f), fall(0.0f, 3.0f);
  std::vector<Query> queries(count);
  for (Query& q : queries) {
    q.x = u(rng);
    q.z = u(rng);
    q.r = 0.5f;
    q.y = map.surface_height(q.x, q.z) + q.r + lift(rng);
    q.vy = -fall(rng);
  }
  if (order == Order::Morton) sort_by_morton(queries);
  return queries;
}

std::vector<Query> falling_queries(std::size_t count, Order order, std::uint32_t seed) {
  const Heightmap& map = rain_terrain().heightmap();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(8.0f, 247.0f), lift(1.0f, 3.0f), speed(30.0f, 300.0f), tilt(-0.2f, 0.2f);
  std::vector<Query> queries(count);
  for (Query& q : queries) {
    q.x = u(rng);
    q.z = u(rng);
    q.r = 0.5f;
    q.y = map.surface_height(q.x, q.z) + q.r + lift(rng);
    const float s = speed(rng);
    q.vx = s * tilt(rng);
    q.vy = -s;
    q.vz = s * tilt(rng);
  }
  if (order == Order::Morton) sort_by_morton(queries);
  return queries;
}

void add_sphere(SphereSoA& s, float x, float y, float z, float r, float vx, float vy, float vz) {
  s.add({x, y, z, vx, vy, vz, 0, 0, 0, r, 1.0f, 1.0f / (0.4f * r * r), 0.5f, 0.5f, 0});
}

SphereSoA make_cloud(Cloud cloud, std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), jitter(-0.3f, 0.3f), vel(-1.0f, 1.0f);
  SphereSoA s;
  s.reserve(n);
  if (cloud == Cloud::Rain) {
    // scenes/scene_terrain_rain.cpp's layout (first layer at y = 13, centred on the terrain).
    const std::size_t side = std::min<std::size_t>(160, static_cast<std::size_t>(std::ceil(std::sqrt(double(n)))));
    const float half = static_cast<float>(side) / 2.0f, spacing = 1.5f;
    for (std::size_t k = 0; k < n; ++k) {
      const float x = 127.5f + (static_cast<float>(k % side) - half) * spacing + jitter(rng);
      const float z = 127.5f + (static_cast<float>((k / side) % side) - half) * spacing + jitter(rng);
      const float y = 13.0f + static_cast<float>(k / (side * side)) * spacing + jitter(rng);
      add_sphere(s, x, y, z, 0.5f, vel(rng), vel(rng), vel(rng));
    }
    return s;
  }
  std::vector<float> radius(n);
  double volume = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    radius[k] = k % 100 == 37 ? 5.0f : 0.25f + 2.25f * unit(rng);
    volume += 4.0 / 3.0 * std::numbers::pi * double(radius[k]) * radius[k] * radius[k];
  }
  const float side = static_cast<float>(std::cbrt(volume / 0.3));
  for (std::size_t k = 0; k < n; ++k)
    add_sphere(s, side * unit(rng), side * unit(rng), side * unit(rng), radius[k], vel(rng), vel(rng), vel(rng));
  return s;
}

}  // namespace hail::micro
