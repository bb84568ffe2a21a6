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

}  // namespace hail::bench
