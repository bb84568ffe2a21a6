#include "query_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "kernel/bvh_build.h"
#include "kernel/flat_bvh.h"
#include "kernel/heightmap.h"
#include "kernel/terrain_triangles.h"
#include "machine_info.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

float rain_height(float x, float z) {
  return 8.0f * std::sin(0.05f * x) * std::cos(0.07f * z) + 3.0f * std::sin(0.21f * x + 0.13f * z);
}

std::vector<Aabb> triangle_bounds(const TerrainTriangles& t) {
  std::vector<Aabb> bounds(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) terrain_triangle_bounds(t, k, bounds[k].min, bounds[k].max);
  return bounds;
}

struct Sphere { float x, y, z, r; };

/// Runs `query` over every sphere `repeats` times; returns ns per query (median of repeats)
/// and the total of what the query returned (hits after the box test), to check agreement.
template <class Query>
std::pair<double, std::uint64_t> time_queries(const std::vector<Sphere>& spheres, int repeats, Query&& query) {
  std::vector<double> ns;
  std::uint64_t hits = 0;
  for (int r = 0; r < repeats; ++r) {
    hits = 0;
    const auto t0 = clock_type::now();
    for (const Sphere& s : spheres) hits += query(s);
    ns.push_back(std::chrono::duration<double, std::nano>(clock_type::now() - t0).count() / double(spheres.size()));
  }
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], hits};
}

int parse_int(const std::vector<std::string>& args, const char* flag, int fallback) {
  for (std::size_t k = 0; k + 1 < args.size(); ++k)
    if (args[k] == flag) return std::stoi(args[k + 1]);
  return fallback;
}

}  // namespace

int query_command(const std::vector<std::string>& args) {
  const int count = parse_int(args, "--queries", 100000);
  const int leaf = parse_int(args, "--leaf", 4);
  const int repeats = parse_int(args, "--repeats", 5);
  if (count < 1 || repeats < 1) throw std::invalid_argument("--queries and --repeats must be >= 1");
  const Heightmap map = Heightmap::from_function(256, 256, {}, rain_height);
  const TerrainTriangles grid_order = build_terrain_triangles(map);
  const std::vector<Aabb> bounds = triangle_bounds(grid_order);
  BvhBuildOptions options;
  options.leaf_size = leaf;
  const FlatBvh bvh = build_flat_bvh(bounds, options);
  std::vector<Aabb> bvh_bounds(bounds.size());
  for (std::size_t k = 0; k < bounds.size(); ++k) bvh_bounds[k] = bounds[bvh.primitive_order[k]];

  // Spheres of radius 0.5 resting on or just above the terrain-rain surface, random (x, z).
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(1.0f, 254.0f), lift(-0.05f, 0.3f);
  std::vector<Sphere> spheres(static_cast<std::size_t>(count));
  for (Sphere& s : spheres) {
    s.x = u(rng);
    s.z = u(rng);
    s.r = 0.5f;
    s.y = map.surface_height(s.x, s.z) + s.r + lift(rng);
  }

  std::printf("hail-bench query: %zu spheres (r 0.5) against terrain-rain's %zu triangles, leaf size %d, median of %d\n",
              spheres.size(), bounds.size(), leaf, repeats);
  std::printf("  machine %s, SIMD %s; %zu BVH nodes\n", cpu_model().c_str(), simd_path().c_str(), bvh.nodes.size());
  std::printf("  %-22s %12s %14s %12s %10s\n", "method", "ns/query", "queries/s", "hits", "nodes/query");

  auto box_hit = [](const Aabb& b, const Sphere& s) { return sphere_overlaps(b, s.x, s.y, s.z, s.r); };
  NodeVisitCount visits;
  for (const Sphere& s : spheres) query_sphere(bvh, s.x, s.y, s.z, s.r, [](std::uint32_t) {}, visits);
  const double nodes_per_query = double(visits.visited) / double(spheres.size());
  const auto stackless = time_queries(spheres, repeats, [&](const Sphere& s) {
    std::uint32_t hits = 0;
    query_sphere(bvh, s.x, s.y, s.z, s.r, [&](std::uint32_t k) { hits += box_hit(bvh_bounds[k], s); });
    return hits;
  });
  const auto stack = time_queries(spheres, repeats, [&](const Sphere& s) {
    std::uint32_t hits = 0;
    query_sphere_stack(bvh, s.x, s.y, s.z, s.r, [&](std::uint32_t k) { hits += box_hit(bvh_bounds[k], s); });
    return hits;
  });
  // The lookup a heightmap allows: the cells under the sphere's x/z footprint, two triangles each.
  const auto grid = time_queries(spheres, repeats, [&](const Sphere& s) {
    const int cells = int(map.cols()) - 1;
    const int i0 = std::max(0, int(std::floor(s.x - s.r))), i1 = std::min(cells - 1, int(std::floor(s.x + s.r)));
    const int j0 = std::max(0, int(std::floor(s.z - s.r))), j1 = std::min(cells - 1, int(std::floor(s.z + s.r)));
    std::uint32_t hits = 0;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t t = 2 * (std::size_t(j) * cells + i);
        hits += box_hit(bounds[t], s) + box_hit(bounds[t + 1], s);
      }
    return hits;
  });
  const std::vector<Sphere> few(spheres.begin(), spheres.begin() + std::min<std::size_t>(spheres.size(), 200));
  const auto brute = time_queries(few, 1, [&](const Sphere& s) {
    std::uint32_t hits = 0;
    for (const Aabb& b : bounds) hits += box_hit(b, s);
    return hits;
  });
  auto row = [&](const char* name, std::pair<double, std::uint64_t> r, const char* nodes) {
    std::printf("  %-22s %12.1f %14.3g %12llu %10s\n", name, r.first, 1e9 / r.first, static_cast<unsigned long long>(r.second), nodes);
  };
  char nodes_text[32];
  std::snprintf(nodes_text, sizeof nodes_text, "%.1f", nodes_per_query);
  row("bvh stackless", stackless, nodes_text);
  row("bvh fixed stack", stack, nodes_text);
  row("grid-cell lookup", grid, "-");
  row("brute force (200 q)", brute, "-");
  std::printf("  stackless / grid time ratio: %.2f; hits agree: %s\n", stackless.first / grid.first,
              stackless.second == stack.second && stack.second == grid.second ? "yes" : "NO");
  return stackless.second == stack.second && stack.second == grid.second ? 0 : 1;
}

int bvh_build_command(const std::vector<std::string>& args) {
  const int max_side = parse_int(args, "--max-side", 1024);
  std::printf("hail-bench bvh-build: BVH over heightmap triangles (terrain-rain's function), one thread\n");
  std::printf("  %-12s %12s %12s %12s %12s\n", "vertices", "triangles", "nodes", "median s", "binned SAH s");
  for (int side : {256, 1024, 4096}) {
    if (side > max_side) {
      std::printf("  %dx%d skipped (pass --max-side %d; about 2 GB and 50 s)\n", side, side, side);
      continue;
    }
    const Heightmap map = Heightmap::from_function(std::uint32_t(side), std::uint32_t(side), {}, rain_height);
    const std::vector<Aabb> bounds = triangle_bounds(build_terrain_triangles(map));
    double seconds[2] = {0, 0};
    std::size_t nodes = 0;
    for (int method = 0; method < 2; ++method) {
      BvhBuildOptions options;
      options.split = method == 0 ? BvhSplit::Median : BvhSplit::BinnedSah;
      const auto t0 = clock_type::now();
      const FlatBvh bvh = build_flat_bvh(bounds, options);
      seconds[method] = std::chrono::duration<double>(clock_type::now() - t0).count();
      if (method == 0) nodes = bvh.nodes.size();
    }
    std::printf("  %-12s %12zu %12zu %12.3f %12.3f\n", (std::to_string(side) + "^2").c_str(), bounds.size(), nodes,
                seconds[0], seconds[1]);
  }
  return 0;
}

}  // namespace hail::bench
