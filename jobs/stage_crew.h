#pragma once
// A crew of threads that runs many short stages in a row with a cheap barrier between them:
// the solver's passes are colour after colour (a step has many such stages, each short:
// docs/benchmarks.md, "Figures behind the code's choices"), and a tbb::parallel_for per stage
// paid its task start and join every time, which is what kept two threads well below twice one
// thread's speed.
//
// After Box2D v3's solver stages: one task per arena thread for the whole sequence. The calling
// thread (the "lead") publishes a stage, claims its blocks like everyone else, and waits until
// every block is done; the other threads spin (briefly, then yield) for the next stage, claim
// blocks of it with a compare-and-swap on one word that holds the stage number and the blocks
// left (the lead takes them from the front, helpers from the back), and leave when the lead says the sequence is over.
//
// Determinism: which thread runs a block never changes what the block computes, and a stage
// only starts after every block of the one before has finished, exactly as with one
// parallel_for per stage. Progress: the lead runs any block nobody else claimed, so the
// sequence finishes even when no other thread ever joins (a busy host arena).
//
// Memory order: a helper's block writes are released by its increment of the done count and
// acquired by the lead's wait; the lead's publication of the next stage releases them again,
// and every claimer acquires that word before its block runs.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <type_traits>
#include <vector>

#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include "jobs/sync_count.h"
#include "soa/grow.h"

namespace hail {

class StageCrew {
 public:
  /// Runs lead(*this) on the calling thread, with the other threads of the current task arena
  /// joining the stages lead publishes through stage(). `max_stages` bounds the number of
  /// stage() calls (their descriptions are kept for the whole sequence, so that a late thread
  /// never reads one being rewritten). With one thread, stage() runs its blocks in order.
  template <class Lead>
  void run(std::size_t max_stages, Lead&& lead) {
    SyncCounts::count_loop();  // the crew's own fork and join, on any thread count
    const int threads = tbb::this_task_arena::max_concurrency();
    solo_ = threads <= 1;
    if (solo_) {
      lead(*this);
      return;
    }
    max_stages_ = max_stages < kMaxStages ? max_stages : kMaxStages;
    if (stages_.size() < max_stages_ + 1) resize_geometric(stages_, max_stages_ + 1);  // O(log n) growths
    published_ = 0;
    claim_.store(0, std::memory_order_relaxed);
    done_.store(0, std::memory_order_relaxed);
    finished_.store(false, std::memory_order_relaxed);
    tbb::task_group helpers;
    for (int t = 1; t < threads; ++t) helpers.run([this] { help(); });
    lead(*this);
    finished_.store(true, std::memory_order_release);
    helpers.wait();
  }

  /// Inside run(): calls f(block) for every block in [0, blocks), on whichever crew threads
  /// claim them, and returns when all have finished. Blocks must not depend on each other.
  template <class F>
  void stage(std::size_t blocks, F&& f) {
    if (blocks == 0) return;
    if (blocks > 1) SyncCounts::count_stage();
    if (solo_ || blocks == 1) {
      for (std::size_t b = 0; b < blocks; ++b) f(b);
      return;
    }
    // More stages than run() was told, or more blocks than a claim word holds: still correct,
    // on this thread.
    if (published_ >= max_stages_ || blocks > kBlockMask) {
      for (std::size_t b = 0; b < blocks; ++b) f(b);
      return;
    }
    const std::uint32_t number = ++published_;
    stages_[number] = Stage{&call<std::remove_reference_t<F>>, &f};
    done_.store(0, std::memory_order_relaxed);  // no block of an earlier stage is still running
    claim_.store(std::uint64_t{number} << kStageShift | blocks, std::memory_order_release);
    const std::uint32_t mine = work_on(number, false);
    std::uint32_t spins = 0;
    while (done_.load(std::memory_order_acquire) + mine < blocks) pause(spins);
  }

 private:
  // The claim word: stage number, then the next block from the front and one past the next
  // block from the back. The lead claims from the front and the helpers from the back, so with
  // two threads each keeps roughly the same half of a colour's chunks from pass to pass (and
  // their bodies in its cache), as tbb::static_partitioner gave.
  static constexpr int kBlockBits = 20;
  static constexpr std::uint64_t kBlockMask = (std::uint64_t{1} << kBlockBits) - 1;
  static constexpr int kStageShift = 2 * kBlockBits;
  static constexpr std::size_t kMaxStages = (std::size_t{1} << (64 - kStageShift)) - 1;

  struct Stage {
    void (*run_block)(const void* f, std::size_t block) = nullptr;  // one indirect call per block, not per contact
    const void* f = nullptr;
  };

  template <class F>
  static void call(const void* f, std::size_t block) {
    (*static_cast<const F*>(f))(block);
  }

  /// Claims and runs blocks of stage `number`, from the back or the front, until none is left
  /// or the stage is over; returns how many it ran. The lead counts its own blocks instead of
  /// adding them to done_.
  std::uint32_t work_on(std::uint32_t number, bool from_back) {
    const Stage& stage = stages_[number];  // written before the stage was published, never again
    std::uint32_t ran = 0;
    std::uint64_t c = claim_.load(std::memory_order_acquire);
    for (;;) {
      const std::uint64_t front = (c >> kBlockBits) & kBlockMask, back = c & kBlockMask;
      if ((c >> kStageShift) != number || front >= back) return ran;
      const std::uint64_t next = from_back ? c - 1 : c + (std::uint64_t{1} << kBlockBits);
      if (!claim_.compare_exchange_weak(c, next, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
      stage.run_block(stage.f, static_cast<std::size_t>(from_back ? back - 1 : front));
      ++ran;
      c = claim_.load(std::memory_order_acquire);
    }
  }

  /// A helper thread's loop: every newly published stage, until the lead finishes.
  void help() {
    std::uint32_t seen = 0;
    std::uint32_t spins = 0;
    for (;;) {
      const auto number = static_cast<std::uint32_t>(claim_.load(std::memory_order_acquire) >> kStageShift);
      if (number != seen) {
        seen = number;
        spins = 0;
        const std::uint32_t ran = work_on(number, true);
        if (ran) done_.fetch_add(ran, std::memory_order_release);
        continue;
      }
      if (finished_.load(std::memory_order_acquire)) return;
      pause(spins);
    }
  }

  /// Busy-wait step: a CPU pause, and after a while a yield, so that an oversubscribed machine
  /// (more crews than cores) still makes progress.
  static void pause(std::uint32_t& spins) {
    if (++spins < 4096) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      __builtin_ia32_pause();
#endif
      return;
    }
    std::this_thread::yield();
  }

  std::vector<Stage> stages_;
  std::size_t max_stages_ = 0;
  std::uint32_t published_ = 0;
  bool solo_ = true;
  std::atomic<std::uint64_t> claim_{0};  // stage number, front block, back end (above)
  std::atomic<std::uint32_t> done_{0};   // blocks of the current stage finished by helpers
  std::atomic<bool> finished_{false};
};

}  // namespace hail
