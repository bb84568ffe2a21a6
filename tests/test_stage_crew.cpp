// jobs/stage_crew.h: every block of every stage runs exactly once, and a stage sees everything
// the stage before it wrote (the solver's colours depend on that), for any arena size; and
// jobs/sync_count.h counts the loops and stages where threads meet. The test
// names say "thread" so that the ThreadSanitizer run (ctest --preset tsan) includes them.

#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "catch.h"
#include "hail/heightmap.h"
#include "hail/world.h"
#include "jobs/parallel_blocks.h"
#include "jobs/stage_crew.h"
#include "jobs/sync_count.h"
#include "kernel/terrain/terrain_parts.h"

namespace {

// Stage s writes value[b] = value[b] + value[b - 1 (wrapping)] of the stage before, read
// from the other buffer: a chain in which a missed, repeated or early block changes the end.
std::vector<std::uint64_t> run_chain(int threads, std::size_t stages, std::size_t blocks, std::size_t max_stages,
                                     std::vector<std::uint32_t>& runs) {
  std::vector<std::uint64_t> front(blocks), back(blocks);
  for (std::size_t b = 0; b < blocks; ++b) front[b] = b + 1;
  runs.assign(stages * blocks, 0);
  hail::StageCrew crew;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    crew.run(max_stages, [&](hail::StageCrew& c) {
      for (std::size_t s = 0; s < stages; ++s) {
        const std::vector<std::uint64_t>& in = s % 2 ? back : front;
        std::vector<std::uint64_t>& out = s % 2 ? front : back;
        // Stages of a few blocks and of one block alternate with wide ones, as colours do.
        const std::size_t count = s % 5 == 4 ? 1 : blocks;
        c.stage(count, [&](std::size_t b) {
          ++runs[s * blocks + b];
          out[b] = in[b] + 3 * in[(b + blocks - 1) % blocks];
        });
        if (count == 1)
          for (std::size_t b = 1; b < blocks; ++b) out[b] = in[b];
      }
    });
  });
  return stages % 2 ? back : front;
}

}  // namespace

TEST_CASE("A stage crew runs every block of every stage once, after the stage before, on 1 to 8 threads",
          "[jobs][thread][threads]") {
  const std::size_t stages = 200, blocks = 37;
  std::vector<std::uint32_t> runs;
  const std::vector<std::uint64_t> one = run_chain(1, stages, blocks, stages, runs);
  for (int threads : {2, 3, 8}) {
    CAPTURE(threads);
    const std::vector<std::uint64_t> many = run_chain(threads, stages, blocks, stages, runs);
    CHECK(many == one);
    for (std::size_t s = 0; s < stages; ++s) {
      const std::size_t count = s % 5 == 4 ? 1 : blocks;
      for (std::size_t b = 0; b < blocks; ++b) REQUIRE(runs[s * blocks + b] == (b < count ? 1u : 0u));
    }
  }
}

TEST_CASE("A stage crew told too few stages runs the rest on the calling thread, with the same result (thread)",
          "[jobs][thread][threads]") {
  std::vector<std::uint32_t> runs;
  const std::vector<std::uint64_t> one = run_chain(1, 60, 16, 60, runs);
  CHECK(run_chain(4, 60, 16, 10, runs) == one);
  CHECK(run_chain(4, 60, 16, 0, runs) == one);
}

TEST_CASE("A stage crew can be run again and again (threads)", "[jobs][thread][threads]") {
  hail::StageCrew crew;
  tbb::task_arena arena(3);
  std::uint64_t total = 0;
  arena.execute([&] {
    for (int round = 0; round < 50; ++round) {
      std::vector<std::uint64_t> v(64, 0);
      crew.run(4, [&](hail::StageCrew& c) {
        for (int s = 0; s < 4; ++s) c.stage(v.size(), [&](std::size_t b) { v[b] += b + 1; });
      });
      for (std::uint64_t x : v) total += x;
    }
  });
  CHECK(total == 50u * 4u * (64u * 65u / 2u));
}

TEST_CASE("Parallel loops and stages of more than one block are counted on any thread count (threads)",
          "[jobs][thread][threads]") {
  for (const int threads : {1, 3}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      const std::uint64_t loops = hail::SyncCounts::loops.load(), stages = hail::SyncCounts::stages.load();
      hail::for_each_block(10, 4, [](std::size_t, std::size_t, std::size_t) {});  // 3 blocks: a loop
      hail::for_each_block(3, 4, [](std::size_t, std::size_t, std::size_t) {});   // 1 block: none
      hail::StageCrew crew;
      crew.run(4, [](hail::StageCrew& c) {  // the crew itself: a loop
        c.stage(5, [](std::size_t) {});     // a stage
        c.stage(1, [](std::size_t) {});     // one block: none
      });
      CHECK(hail::SyncCounts::loops.load() - loops == 2);
      CHECK(hail::SyncCounts::stages.load() - stages == 1);
    });
  }
}

TEST_CASE("A step's parallel loops and solver stages are the same on 2 and 3 threads (threads)",
          "[jobs][thread][threads]") {
  auto counts = [](int threads) {
    hail::WorldSettings settings;
    settings.threads = threads;
    hail::World world(settings);
    world.set_terrain(std::make_shared<const hail::Terrain>(hail::Heightmap::from_function(
        64, 64, hail::HeightmapParams{}, [](float x, float z) { return 0.1f * std::sin(0.3f * x) * std::cos(0.2f * z); })));
    for (int i = 0; i < 2000; ++i)
      world.add_sphere({.position = {4.0f + float(i % 40) * 1.4f, 1.0f + float(i / 1600) * 1.4f, 4.0f + float((i / 40) % 40) * 1.4f},
                        .radius = 0.5f,
                        .mass = 1.0f});
    std::pair<std::size_t, std::size_t> sum{0, 0};
    for (int step = 0; step < 30; ++step) {
      world.step(1.0f / 60.0f);
      sum.first += world.last_step_stats().parallel_loops;
      sum.second += world.last_step_stats().crew_stages;
    }
    return sum;
  };
  const auto two = counts(2);
  CHECK(two.first > 30);  // several loops a step
  CHECK(two.second > 0);
  CHECK(counts(3) == two);
}
