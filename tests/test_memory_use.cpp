// Memory figures of hail-bench (bench/memory_use.h) and Terrain::memory_bytes: the heap a run
// holds, and how the scale command's memory limit estimates a count it has not run.

#include <cstring>
#include <memory>
#include <vector>

#include "bench/memory_use.h"
#include "bench/scene_run.h"
#include "bench/scenes.h"
#include "catch.h"
#include "kernel/terrain.h"

using namespace hail;

TEST_CASE("The heap in use grows by what is allocated and shrinks when it is freed", "[bench][memory]") {
  const auto before = bench::heap_bytes_in_use();
  if (!before) return;  // the C library cannot report it (not glibc 2.33 or later): nothing to check
  constexpr std::size_t kBytes = 8u << 20;
  auto block = std::make_unique<char[]>(kBytes);
  std::memset(block.get(), 1, kBytes);
  const auto during = bench::heap_bytes_in_use();
  REQUIRE(during);
  CHECK(*during >= *before + kBytes);
  block.reset();
  const auto after = bench::heap_bytes_in_use();
  REQUIRE(after);
  CHECK(*after < *before + kBytes / 2);
}

TEST_CASE("format_bytes gives three significant digits in decimal units", "[bench][memory]") {
  CHECK(bench::format_bytes(512) == "512 B");
  CHECK(bench::format_bytes(1234) == "1.23 kB");
  CHECK(bench::format_bytes(16.5e6) == "16.5 MB");
  CHECK(bench::format_bytes(123.4e9) == "123 GB");
}

TEST_CASE("Terrain::memory_bytes counts its heights, triangles, BVH and triangle boxes", "[bench][memory]") {
  // terrain-rain's map: 256^2 heights, 130,050 triangles of 22 floats and an edge byte, a box each.
  const bench::Scene scene = bench::build_terrain_rain({.spheres = 1, .threads = 1});
  const Terrain& terrain = *scene.world->terrain();
  const std::size_t triangles = terrain.triangles().size();
  REQUIRE(triangles == 130050);
  const std::size_t at_least = 256 * 256 * sizeof(float) + triangles * (22 * sizeof(float) + 1 + sizeof(Aabb)) +
                               terrain.bvh().nodes.size() * sizeof(FlatNode) + triangles * sizeof(std::uint32_t);
  CHECK(terrain.memory_bytes() >= at_least);
  CHECK(terrain.memory_bytes() < 2 * at_least);  // capacities, not a multiple of the sizes
}

TEST_CASE("A run reports the heap it holds: the terrain and more than each sphere's state", "[bench][memory]") {
  if (!bench::heap_bytes_in_use()) return;  // the C library cannot report it
  bench::RunOptions options;
  options.steps = 20;
  options.progress = false;
  const bench::RunResult r = bench::run_scene(bench::find_scene("terrain-rain"), {.spheres = 2000, .threads = 1}, options);
  CHECK(r.heap_measured);
  CHECK(r.terrain_bytes > 0);
  CHECK(r.heap_after_setup >= r.terrain_bytes);
  CHECK(r.heap_at_end >= r.heap_after_setup);
  // Each sphere's SoA state alone is 14 floats and a flag word; the solver adds a 64-byte body.
  CHECK(r.bytes_per_sphere() > 14 * sizeof(float) + 4 + 64);
  CHECK(r.bytes_per_sphere() < 100000);
}
