#pragma once
// Optional per-thread phase trace, for Chrome's trace-event viewer (Perfetto,
// chrome://tracing): when enabled, every block of work a phase runs records its start and end on
// the thread that ran it; at the end of a step each thread's blocks of one phase collapse into
// one slice (first start .. last end). So a step shows, per thread, when it worked on which
// phase, and the gaps show where threads waited. Off by default; when off, recording is one
// branch per block. Each thread writes only its own row of slots: no locks, no atomics.

#include <chrono>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <oneapi/tbb/task_arena.h>

namespace hail {

/// The phases of a step (kernel/world/step_pipeline.cpp), in order.
enum class Phase : std::uint8_t {
  Reorder,
  Predict,
  DetectTerrain,
  DetectPairs,
  Solve,
  Sweep,
  Integrate,
  Depenetrate,
  Islands,  ///< sleeping: waking before the solve, islands and sleep after the step (WorldSettings::sleep)
  Count
};

/// The phase's name as hail-bench prints it.
[[nodiscard]] constexpr const char* phase_name(Phase p) {
  constexpr const char* names[] = {"reorder", "predict",   "detect-terrain", "detect-pairs", "solve",
                                   "sweep",   "integrate", "depenetrate",    "islands"};
  return names[static_cast<int>(p)];
}

/// One thread's work on one phase in one step; times in microseconds since the trace began.
struct TraceSlice {
  Phase phase;
  int thread;
  std::uint64_t step;
  double start_us, end_us;
};

class PhaseTrace {
 public:
  /// Turns recording on (sized for `threads` arena slots) or off; clears what was recorded.
  void enable(bool on, int threads) {
    enabled_ = on;
    threads_ = threads < 1 ? 1 : threads;
    slots_.assign(static_cast<std::size_t>(threads_) * kPhases, Slot{});
    slices_.clear();
    origin_ = std::chrono::steady_clock::now();
  }
  [[nodiscard]] bool enabled() const { return enabled_; }

  /// Microseconds since enable().
  [[nodiscard]] double now_us() const {
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - origin_).count();
  }

  /// Records [start, end] of work on `phase` by the calling thread.
  void record(Phase phase, double start_us, double end_us) {
    int thread = tbb::this_task_arena::current_thread_index();
    if (thread < 0 || thread >= threads_) thread = threads_ - 1;  // outside the arena: last row
    Slot& s = slots_[static_cast<std::size_t>(thread) * kPhases + static_cast<std::size_t>(phase)];
    if (start_us < s.start) s.start = start_us;
    if (end_us > s.end) s.end = end_us;
  }

  /// Turns the step's slots into slices (threads ascending, phases in order) and resets them.
  void finish_step(std::uint64_t step) {
    for (int t = 0; t < threads_; ++t)
      for (std::size_t p = 0; p < kPhases; ++p) {
        Slot& s = slots_[static_cast<std::size_t>(t) * kPhases + p];
        if (s.end >= s.start) slices_.push_back({static_cast<Phase>(p), t, step, s.start, s.end});
        s = Slot{};
      }
  }

  /// Every slice recorded since enable().
  [[nodiscard]] std::span<const TraceSlice> slices() const { return slices_; }

 private:
  static constexpr std::size_t kPhases = static_cast<std::size_t>(Phase::Count);
  struct Slot {
    double start = std::numeric_limits<double>::infinity();
    double end = -std::numeric_limits<double>::infinity();
  };
  bool enabled_ = false;
  int threads_ = 1;
  std::vector<Slot> slots_;
  std::vector<TraceSlice> slices_;
  std::chrono::steady_clock::time_point origin_;
};

/// Records the enclosing scope as work on `phase` by this thread, when the trace is on.
class ScopedTraceRecord {
 public:
  ScopedTraceRecord(PhaseTrace& trace, Phase phase)
      : trace_(trace), phase_(phase), start_(trace.enabled() ? trace.now_us() : 0.0) {}
  ~ScopedTraceRecord() {
    if (trace_.enabled()) trace_.record(phase_, start_, trace_.now_us());
  }
  ScopedTraceRecord(const ScopedTraceRecord&) = delete;
  ScopedTraceRecord& operator=(const ScopedTraceRecord&) = delete;

 private:
  PhaseTrace& trace_;
  Phase phase_;
  double start_;
};

}  // namespace hail
