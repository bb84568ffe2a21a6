// jobs/stage_crew.h: every block of every stage runs exactly once, and a stage sees everything
// the stage before it wrote (the solver's colours depend on that), for any arena size. The test
// names say "thread" so that the ThreadSanitizer run (ctest --preset tsan) includes them.

#include <cstdint>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "catch.h"
#include "jobs/stage_crew.h"

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
