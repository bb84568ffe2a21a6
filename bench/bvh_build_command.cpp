#include "bvh_build_command.h"

#include <chrono>
#include <cstdio>

#include "cli.h"
#include "hail/heightmap.h"
#include "kernel/bvh/bvh_build.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/terrain/terrain_parts.h"
#include "kernel/terrain/terrain_triangles.h"
#include "scenes/scenes.h"

namespace hail::bench {
namespace {

std::vector<Aabb> triangle_bounds(const TerrainTriangles& t) {
  std::vector<Aabb> bounds(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) terrain_triangle_bounds(t, k, bounds[k].min, bounds[k].max);
  return bounds;
}

}  // namespace

int bvh_build_command(const BvhBuildCommandOptions& o) {
  const int max_side = o.max_side;
  std::printf(
      "hail-bench bvh-build: BVH over heightmap triangles (terrain-rain's function), leaf size %u, one thread\n",
      Terrain::kDefaultLeafSize);
  std::printf("  %-12s %12s %12s %12s %12s\n", "vertices", "triangles", "nodes", "median s", "binned SAH s");
  for (int side : {256, 1024, 4096}) {
    if (side > max_side) {
      std::printf("  %dx%d skipped (pass --max-side %d; about 2 GB and 50 s)\n", side, side, side);
      continue;
    }
    const Heightmap map = Heightmap::from_function(std::uint32_t(side), std::uint32_t(side), {}, terrain_rain_height);
    const std::vector<Aabb> bounds = triangle_bounds(build_terrain_triangles(map));
    double seconds[2] = {0, 0};
    std::size_t nodes = 0;
    for (int method = 0; method < 2; ++method) {
      BvhBuildOptions options;
      options.split = method == 0 ? BvhSplit::Median : BvhSplit::BinnedSah;
      options.leaf_size = static_cast<int>(Terrain::kDefaultLeafSize);  // as a Terrain builds it
      const auto t0 = std::chrono::steady_clock::now();
      const FlatBvh bvh = build_flat_bvh(bounds, options);
      seconds[method] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (method == 0) nodes = bvh.nodes.size();
    }
    std::printf("  %-12s %12zu %12zu %12.3f %12.3f\n", (std::to_string(side) + "^2").c_str(), bounds.size(), nodes,
                seconds[0], seconds[1]);
  }
  return 0;
}

// The flags of `hail-bench bvh-build` (bench/cli.h's rules).

void add_bvh_build_options(CLI::App& app, BvhBuildCommandOptions& o) {
  app.description("BVH build time (median split and binned SAH) for 256^2, 1024^2 (and 4096^2) heightmaps");
  add_count(app, "--max-side", o.max_side, 1, 65536, "the largest heightmap side built (4096 takes about 2 GB)");
}

int bvh_build_command(const std::vector<std::string>& args) {
  const std::optional<BvhBuildCommandOptions> parsed = parse_command("bvh-build", add_bvh_build_options, args);
  return parsed ? bvh_build_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
