#pragma once
// How much memory a run takes, for `hail-bench run` and `hail-bench scale`: the heap the process
// has in use (glibc's mallinfo2, which counts every live malloc block, mmap'd ones included) and
// the memory the machine has available (Linux's MemAvailable). Both read at one moment, outside
// the timed steps.

#include <cstddef>
#include <optional>
#include <string>

namespace hail::bench {

/// Bytes the process has allocated and not yet freed; nullopt where the C library cannot say
/// (not glibc 2.33 or later).
[[nodiscard]] std::optional<std::size_t> heap_bytes_in_use();

/// Memory the machine can give a process without swapping (/proc/meminfo MemAvailable, else
/// free physical pages); nullopt where neither can be read.
[[nodiscard]] std::optional<std::size_t> available_memory_bytes();

/// "12.3 MB", "1.52 GB": bytes in decimal units, three significant digits.
[[nodiscard]] std::string format_bytes(double bytes);

/// The most heap a terrain-rain sphere took in the measured runs (2,026 bytes at 1M spheres,
/// where the piles are deepest; 1.2-1.7 kB up to 512k), rounded up: what `hail-bench run`
/// assumes before it builds a scene, to refuse one that could not fit.
inline constexpr double kBytesPerSphereGuide = 2100.0;

/// What a terrain takes at its peak while it is built, per heightmap cell: two triangles at
/// about 140 bytes kept and twice that during the build (include/hail/terrain.h), plus the heights,
/// rounded up (measured: 480 bytes a cell, the peak RSS of `hail-bench run --scene` with a
/// 2049^2 terrain-rain map less that of a 1025^2 one). What a scene file's terrain is checked against the memory limit with, before
/// anything is allocated for it.
inline constexpr double kTerrainBytesPerCellGuide = 600.0;

/// The memory limit of `--memory-limit GB`: gb < 0 (not given) 80% of the memory available now
/// (0 when unknown), 0 none (returns 0), else gb * 1e9 bytes.
[[nodiscard]] double memory_limit_bytes(double gb);

/// How memory_limit_bytes(gb) came about, for messages: "80% of the memory available now",
/// "--memory-limit", "none".
[[nodiscard]] std::string describe_memory_limit(double gb, double limit_bytes);

/// A memory limit and how it came about, for readers that refuse what would not fit.
struct MemoryLimit {
  double bytes = 0.0;       ///< 0: no limit
  std::string description;  ///< describe_memory_limit's words
};

/// memory_limit_bytes(gb) with describe_memory_limit's words.
[[nodiscard]] MemoryLimit memory_limit(double gb);

/// "needs about 1.2 GB (WHY), over the memory limit of ...; --memory-limit GB sets it, 0 turns
/// the check off": the end of every message refusing something for the memory limit.
[[nodiscard]] std::string over_memory_limit(double estimate_bytes, const std::string& why, const MemoryLimit& limit);

}  // namespace hail::bench
