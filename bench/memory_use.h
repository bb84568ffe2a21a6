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

/// The memory limit of `--memory-limit GB`: gb < 0 (not given) 80% of the memory available now
/// (0 when unknown), 0 none (returns 0), else gb * 1e9 bytes.
[[nodiscard]] double memory_limit_bytes(double gb);

/// How memory_limit_bytes(gb) came about, for messages: "80% of the memory available now",
/// "--memory-limit", "none".
[[nodiscard]] std::string describe_memory_limit(double gb, double limit_bytes);

}  // namespace hail::bench
