#pragma once
// How often a step's threads meet: each parallel loop of more than one block (for_each_block
// and kin) forks and joins them, and each solver stage of more than one block
// (StageCrew::stage) is a barrier. A short step on many threads is bounded by how many such
// meetings it has and what each costs, not by its work (issue 48: at 4k spheres 16 threads
// gave 2.7x one). A loop counts whatever the thread count (one thread runs the same blocks in
// order), so the counts are the same on every thread count above one; on one thread the step
// colours its contacts without tiles and sorts serially, two loops fewer. World::step reads
// them around a step (StepStats::parallel_loops, StepStats::crew_stages).

#include <atomic>
#include <cstdint>

namespace hail {

/// Process-wide counters (relaxed atomics: a few hundred increments a step). A process that
/// steps two worlds at once counts both worlds' meetings in each step's figures.
struct SyncCounts {
  static inline std::atomic<std::uint64_t> loops{0};
  static inline std::atomic<std::uint64_t> stages{0};
  static void count_loop() { loops.fetch_add(1, std::memory_order_relaxed); }
  static void count_stage() { stages.fetch_add(1, std::memory_order_relaxed); }
};

}  // namespace hail
