#include "query_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "cli.h"
#include "hail/heightmap.h"
#include "kernel/bvh/bvh_build.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/bvh/flat_node.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/morton.h"
#include "kernel/terrain/terrain_parts.h"
#include "kernel/terrain/terrain_triangles.h"
#include "scenes/machine_info.h"
#include "scenes/scenes.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

std::vector<Aabb> triangle_bounds(const TerrainTriangles& t) {
  std::vector<Aabb> bounds(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) terrain_triangle_bounds(t, k, bounds[k].min, bounds[k].max);
  return bounds;
}

struct Sphere {
  float x, y, z, r;
};

/// Runs `query` over the spheres in groups of `group` (the last may be short), `repeats`
/// times; returns ns per sphere (median of repeats) and the total of what the query returned
/// (hits after the box test), to check agreement.
template <class Query>
std::pair<double, std::uint64_t> time_groups(const std::vector<Sphere>& spheres, std::size_t group, int repeats,
                                             Query&& query) {
  std::vector<double> ns;
  std::uint64_t hits = 0;
  for (int r = 0; r < repeats; ++r) {
    hits = 0;
    const auto t0 = clock_type::now();
    for (std::size_t first = 0; first < spheres.size(); first += group)
      hits += query(std::span<const Sphere>(spheres).subspan(first, std::min(group, spheres.size() - first)));
    ns.push_back(std::chrono::duration<double, std::nano>(clock_type::now() - t0).count() / double(spheres.size()));
  }
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], hits};
}

/// time_groups one sphere at a time.
template <class Query>
std::pair<double, std::uint64_t> time_queries(const std::vector<Sphere>& spheres, int repeats, Query&& query) {
  return time_groups(spheres, 1, repeats, [&](std::span<const Sphere> one) { return query(one[0]); });
}

/// The packet walk of the active SIMD path (SimdKernels::count_packet_hits) over all spheres,
/// `repeats` times: ns per sphere (median) and the hits, as time_groups gives them.
std::pair<double, std::uint64_t> time_packets(const std::vector<Sphere>& spheres, int repeats, const FlatBvh& bvh,
                                              const std::vector<Aabb>& bounds, PacketLeafTest test) {
  std::vector<float> x, y, z, r;
  for (const Sphere& s : spheres) x.push_back(s.x), y.push_back(s.y), z.push_back(s.z), r.push_back(s.r);
  const SimdKernels& kernels = simd_kernels();
  std::vector<double> ns;
  std::uint64_t hits = 0;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = clock_type::now();
    hits = kernels.count_packet_hits(bvh, bounds.data(), x.data(), y.data(), z.data(), r.data(), spheres.size(), test,
                                     nullptr);
    ns.push_back(std::chrono::duration<double, std::nano>(clock_type::now() - t0).count() / double(spheres.size()));
  }
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], hits};
}

/// The spheres sorted by the Morton code of their centres over the terrain's bounds.
std::vector<Sphere> morton_sorted(std::vector<Sphere> spheres, const Aabb& bounds) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(spheres.size());
  for (std::uint32_t k = 0; k < spheres.size(); ++k)
    keyed[k] = {morton_code_3d(bounds, spheres[k].x, spheres[k].y, spheres[k].z), k};
  std::sort(keyed.begin(), keyed.end());
  std::vector<Sphere> sorted(spheres.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) sorted[k] = spheres[keyed[k].second];
  return sorted;
}

}  // namespace

int query_command(const QueryOptions& o) {
  const int count = o.queries, leaf = o.leaf, repeats = o.repeats;
  const Heightmap map = Heightmap::from_function(256, 256, {}, terrain_rain_height);
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

  Aabb terrain_box = empty_aabb();
  for (const Aabb& b : bounds) grow(terrain_box, b);
  const std::vector<Sphere> in_morton_order = morton_sorted(spheres, terrain_box);

  std::printf(
      "hail-bench query: %zu spheres (r 0.5) against terrain-rain's %zu triangles, leaf size %d, median of %d\n",
      spheres.size(), bounds.size(), leaf, repeats);
  std::printf("  machine %s, SIMD %s; %zu BVH nodes; packet width %zu (lanes per node test)\n", cpu_model().c_str(),
              simd_description().c_str(), bvh.nodes.size(), simd_kernels().width);
  std::printf("  %-28s %-8s %12s %14s %12s %12s\n", "method", "order", "ns/query", "queries/s", "hits", "nodes/query");

  auto box_hit = [](const Aabb& b, const Sphere& s) { return sphere_overlaps(b, s.x, s.y, s.z, s.r); };
  auto stackless = [&](const Sphere& s) {
    std::uint32_t hits = 0;
    query_sphere(bvh, s.x, s.y, s.z, s.r, [&](std::uint32_t k) { hits += box_hit(bvh_bounds[k], s); });
    return hits;
  };
  auto stack = [&](const Sphere& s) {
    std::uint32_t hits = 0;
    query_sphere_stack(bvh, s.x, s.y, s.z, s.r, [&](std::uint32_t k) { hits += box_hit(bvh_bounds[k], s); });
    return hits;
  };
  // The lookup a heightmap allows: the cells under the sphere's x/z footprint, two triangles each.
  auto grid = [&](const Sphere& s) {
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
  };
  auto nodes_per_query = [&](const std::vector<Sphere>& order, bool packets) {
    if (packets) {
      std::vector<float> x, y, z, r;
      for (const Sphere& s : order) x.push_back(s.x), y.push_back(s.y), z.push_back(s.z), r.push_back(s.r);
      std::uint64_t nodes = 0;
      (void)simd_kernels().count_packet_hits(bvh, bvh_bounds.data(), x.data(), y.data(), z.data(), r.data(),
                                             order.size(), PacketLeafTest::LeafCandidates, &nodes);
      return double(nodes) / double(order.size());
    }
    NodeVisitCount visits;
    for (const Sphere& s : order)
      query_sphere(
          bvh, s.x, s.y, s.z, s.r, [](std::uint32_t) {}, visits);
    return double(visits.visited) / double(order.size());
  };

  struct Row {
    const char* method;
    const char* order;
    std::pair<double, std::uint64_t> result;
    double nodes;  // < 0: not a BVH walk
  };
  std::vector<Row> rows;
  const std::pair<const char*, const std::vector<Sphere>*> orders[] = {{"random", &spheres},
                                                                       {"morton", &in_morton_order}};
  for (const auto& [order_name, order] : orders) {
    rows.push_back(
        {"bvh stackless", order_name, time_queries(*order, repeats, stackless), nodes_per_query(*order, false)});
    rows.push_back({"bvh fixed stack", order_name, time_queries(*order, repeats, stack), rows.back().nodes});
    rows.push_back({"bvh packet", order_name,
                    time_packets(*order, repeats, bvh, bvh_bounds, PacketLeafTest::LeafCandidates),
                    nodes_per_query(*order, true)});
    rows.push_back({"bvh packet, SIMD leaf boxes", order_name,
                    time_packets(*order, repeats, bvh, bvh_bounds, PacketLeafTest::LeafBoxes), rows.back().nodes});
    rows.push_back({"grid-cell lookup", order_name, time_queries(*order, repeats, grid), -1.0});
  }
  const std::vector<Sphere> few(spheres.begin(), spheres.begin() + std::min<std::size_t>(spheres.size(), 200));
  const auto brute = time_queries(few, 1, [&](const Sphere& s) {
    std::uint32_t hits = 0;
    for (const Aabb& b : bounds) hits += box_hit(b, s);
    return hits;
  });

  bool agree = true;
  for (const Row& r : rows) {
    char nodes_text[32] = "-";
    if (r.nodes >= 0) std::snprintf(nodes_text, sizeof nodes_text, "%.1f", r.nodes);
    std::printf("  %-28s %-8s %12.1f %14.3g %12llu %12s\n", r.method, r.order, r.result.first, 1e9 / r.result.first,
                static_cast<unsigned long long>(r.result.second), nodes_text);
    agree = agree && r.result.second == rows.front().result.second;
  }
  std::printf("  %-28s %-8s %12.1f %14.3g %12llu %12s\n", "brute force (200 q)", "random", brute.first,
              1e9 / brute.first, static_cast<unsigned long long>(brute.second), "-");
  // Ratios against the grid lookup in the same order (nodes/query counts a packet's node tests
  // once for all its lanes, divided by the lanes).
  constexpr std::size_t kRowsPerOrder = 5;
  for (std::size_t o = 0; o < 2; ++o) {
    const Row* first = &rows[kRowsPerOrder * o];
    const double grid_ns = first[4].result.first;
    std::printf(
        "  %s order, time / grid: stackless %.2f, fixed stack %.2f, packet %.2f, packet with SIMD leaf boxes %.2f\n",
        first->order, first[0].result.first / grid_ns, first[1].result.first / grid_ns, first[2].result.first / grid_ns,
        first[3].result.first / grid_ns);
  }
  std::printf("  hits agree across methods and orders: %s\n", agree ? "yes" : "NO");
  return agree ? 0 : 1;
}

// The flags of `hail-bench query` (bench/cli.h's rules).

void add_query_options(CLI::App& app, QueryOptions& o) {
  app.description("terrain query microbenchmark: BVH walks (stackless, fixed stack, packet), grid lookup, brute force");
  add_count(app, "--queries", o.queries, 1, 100'000'000, "spheres queried");
  add_count(app, "--leaf", o.leaf, 1, kMaxLeafSize, "triangles per BVH leaf (default the terrain's)");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
}

int query_command(const std::vector<std::string>& args) {
  const std::optional<QueryOptions> parsed = parse_command("query", add_query_options, args);
  return parsed ? query_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
