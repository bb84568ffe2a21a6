#pragma once
// jobs/ decides how a step's work is spread over threads. Everything here splits work into
// blocks whose boundaries depend only on the problem size, never on the thread count, and
// callers merge per-block output in block order: that is what makes a step bitwise identical
// for 1 thread or 16.

#include <algorithm>
#include <cstddef>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include "jobs/sync_count.h"

namespace hail {

/// Calls f(block, begin, end) for the fixed blocks [k * block_size, (k+1) * block_size) of
/// [0, count), in parallel when there is more than one block, blocks handed out by `partitioner`.
template <class Partitioner, class F>
void for_each_block_partitioned(std::size_t count, std::size_t block_size, const Partitioner& partitioner, F&& f) {
  const std::size_t blocks = (count + block_size - 1) / block_size;
  if (blocks == 0) return;
  if (blocks == 1) {
    f(std::size_t{0}, std::size_t{0}, count);
    return;
  }
  SyncCounts::count_loop();
  // One thread in this arena: the blocks in order, without making a task per block (a step
  // enters a few hundred of these loops). The same blocks, so the same result.
  if (tbb::this_task_arena::max_concurrency() == 1) {
    for (std::size_t b = 0; b < blocks; ++b) f(b, b * block_size, std::min(count, (b + 1) * block_size));
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, blocks, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) f(b, b * block_size, std::min(count, (b + 1) * block_size));
      },
      partitioner);
}

/// for_each_block_partitioned with each block a task of its own (tbb::simple_partitioner).
template <class F>
void for_each_block(std::size_t count, std::size_t block_size, F&& f) {
  for_each_block_partitioned(count, block_size, tbb::simple_partitioner(), f);
}

/// for_each_block with the blocks split evenly over the threads in the same way on every call
/// (tbb::static_partitioner): block k lands on the same thread each time, so a loop repeated
/// many times over the same data (the solver's passes, colour after colour) finds it in that
/// thread's cache. Which thread runs a block never changes a result.
template <class F>
void for_each_block_pinned(std::size_t count, std::size_t block_size, F&& f) {
  for_each_block_partitioned(count, block_size, tbb::static_partitioner(), f);
}

/// Number of fixed blocks of block_size covering count items.
constexpr std::size_t block_count(std::size_t count, std::size_t block_size) {
  return (count + block_size - 1) / block_size;
}

}  // namespace hail
