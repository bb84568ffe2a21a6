// Memory figures of hail-bench (scenes/memory_use.h) and Terrain::memory_bytes: the heap a run
// holds, and how the scale command's memory limit estimates a count it has not run.

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/run_command.h"
#include "tests/catch.h"
#include "kernel/terrain/terrain_parts.h"
#include "scenes/memory_use.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"

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
  const bench::RunResult r =
      bench::run_scene(bench::find_scene("terrain-rain"), {.spheres = 2000, .threads = 1}, options);
  CHECK(r.heap_measured);
  CHECK(r.terrain_bytes > 0);
  CHECK(r.heap_after_setup >= r.terrain_bytes);
  CHECK(r.heap_at_end >= r.heap_after_setup);
  // Each sphere's SoA state alone is 14 floats and a flag word; the solver adds a 64-byte body.
  CHECK(r.bytes_per_sphere() > 14 * sizeof(float) + 4 + 64);
  CHECK(r.bytes_per_sphere() < 100000);
}

TEST_CASE("The memory limit: default 80% of what is available, 0 none, else the gigabytes given", "[bench][memory]") {
  CHECK(bench::memory_limit_bytes(0.0) == 0.0);
  CHECK(bench::memory_limit_bytes(2.5) == 2.5e9);
  const auto available = bench::available_memory_bytes();
  // Within 1%, not equal: the memory available moves between the two reads while other tests
  // run beside this one (ctest -j; CI once saw 95 kB of 24.8 GB between them).
  if (available) CHECK(bench::memory_limit_bytes(-1.0) == Approx(0.8 * double(*available)).epsilon(0.01));
  CHECK(bench::describe_memory_limit(0.0, 0.0).find("none") != std::string::npos);
  CHECK(bench::describe_memory_limit(2.5, 2.5e9).find("2.50 GB") != std::string::npos);
}

TEST_CASE("hail-bench run refuses a sphere count over the memory limit before building anything", "[bench][memory]") {
  // 10M spheres at 2.1 kB each are about 21 GB: over a 1 GB limit, refused at once (a build
  // would take minutes); the message names the estimate and the way out.
  try {
    bench::run_command({"terrain-rain", "--spheres", "10000000", "--memory-limit", "1"});
    FAIL("run_command accepted 10M spheres under a 1 GB limit");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.find("21.0 GB") != std::string::npos);
    CHECK(message.find("1.00 GB (--memory-limit)") != std::string::npos);
    CHECK(message.find("--memory-limit GB sets it, 0 turns the check off") != std::string::npos);
  }
  CHECK_THROWS_AS(bench::run_command({"terrain-rain", "--memory-limit", "-2"}), std::invalid_argument);
}
